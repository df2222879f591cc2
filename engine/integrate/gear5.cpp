#include "integrate/gear5.hpp"

#include "contact/pair_kernel_simd.hpp"
#include "integrate/flat_runs.hpp"
#include "integrate/rotation.hpp"

#include <algorithm>
#include <cmath>

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#endif

namespace wiredem::engine {
namespace {

// The prediction x_k ← Σ_{j≥k} C(j,k) x_j (Pascal triangle) is split in two:
// the predictor writes only x₀ and x₁, the derivatives the force stages read;
// the corrector predicts x₂…x₅ from the stored values itself, on the fly.
// That spares writing four arrays back and reading them again. (Between the
// two, x₂…x₅ still hold the last corrected values.)
//
// The loops below treat the six derivative arrays of a run of consecutive
// bodies as flat arrays of doubles (integrate/flat_runs.hpp). They never
// overlap; passing them as __restrict parameters lets the compiler keep values
// in registers across the stores and vectorise the loops. The arithmetic per
// element is the one of the Vec3 expressions it replaces, operation for
// operation, so the results are bit for bit the same.

// Both loops are built twice, for AVX2 and for the baseline (SSE2), from
// one text (always inlined into a wrapper of each target); the AVX2 one runs
// where the SIMD paths do (simd_isa(), contact/pair_kernel_simd.hpp): four
// doubles per instruction instead of two. Neither fuses a multiply–add (the
// build has -ffp-contract=off, and AVX2 does not bring FMA), so both give the
// same bits. (Not target_clones: its load-time resolver runs before
// ThreadSanitizer's runtime is up and crashes an instrumented program.)

/// x₀ and x₁ predicted in place, over n doubles.
[[gnu::always_inline]] inline void predict_flat(double* __restrict x0, double* __restrict x1,
    const double* __restrict x2, const double* __restrict x3, const double* __restrict x4,
    const double* __restrict x5, std::size_t n)
{
    for (std::size_t j = 0; j < n; ++j) {
        x0[j] += x1[j] + x2[j] + x3[j] + x4[j] + x5[j];
        x1[j] += 2.0 * x2[j] + 3.0 * x3[j] + 4.0 * x4[j] + 5.0 * x5[j];
    }
}

/// x₂…x₅ predicted, then every derivative corrected by Δ = target − x₂(predicted), over n doubles.
[[gnu::always_inline]] inline void correct_flat(double* __restrict x0, double* __restrict x1,
    double* __restrict x2, double* __restrict x3, double* __restrict x4, double* __restrict x5,
    const double* __restrict target, std::size_t n)
{
    constexpr const double* c = gear5_corrector;
    for (std::size_t j = 0; j < n; ++j) {
        const double p2 = x2[j] + (3.0 * x3[j] + 6.0 * x4[j] + 10.0 * x5[j]);
        const double p3 = x3[j] + (4.0 * x4[j] + 10.0 * x5[j]);
        const double p4 = x4[j] + 5.0 * x5[j];
        const double delta = target[j] - p2;
        x0[j] += c[0] * delta;
        x1[j] += c[1] * delta;
        x2[j] = p2 + c[2] * delta;
        x3[j] = p3 + c[3] * delta;
        x4[j] = p4 + c[4] * delta;
        x5[j] += c[5] * delta;
    }
}

using PredictFlat = void (*)(double*, double*, const double*, const double*, const double*, const double*, std::size_t);
using CorrectFlat = void (*)(double*, double*, double*, double*, double*, double*, const double*, std::size_t);

void predict_flat_baseline(double* __restrict x0, double* __restrict x1, const double* __restrict x2,
    const double* __restrict x3, const double* __restrict x4, const double* __restrict x5, std::size_t n)
{
    predict_flat(x0, x1, x2, x3, x4, x5, n);
}
void correct_flat_baseline(double* __restrict x0, double* __restrict x1, double* __restrict x2,
    double* __restrict x3, double* __restrict x4, double* __restrict x5, const double* __restrict target, std::size_t n)
{
    correct_flat(x0, x1, x2, x3, x4, x5, target, n);
}
#if defined(__x86_64__)
[[WIREDEM_AVX2_TARGET]] void predict_flat_avx2(double* __restrict x0, double* __restrict x1,
    const double* __restrict x2, const double* __restrict x3, const double* __restrict x4,
    const double* __restrict x5, std::size_t n)
{
    predict_flat(x0, x1, x2, x3, x4, x5, n);
}
[[WIREDEM_AVX2_TARGET]] void correct_flat_avx2(double* __restrict x0, double* __restrict x1, double* __restrict x2,
    double* __restrict x3, double* __restrict x4, double* __restrict x5, const double* __restrict target, std::size_t n)
{
    correct_flat(x0, x1, x2, x3, x4, x5, target, n);
}
#endif

/// The predictor and corrector loops of the instruction set in use.
PredictFlat predictor()
{
#if defined(__x86_64__)
    if (simd_isa() != SimdIsa::none) return &predict_flat_avx2;
#endif
    return &predict_flat_baseline;
}
CorrectFlat corrector()
{
#if defined(__x86_64__)
    if (simd_isa() != SimdIsa::none) return &correct_flat_avx2;
#endif
    return &correct_flat_baseline;
}

/// Predicts x₀ and x₁ of bodies [b, e) in place.
void predict_position_and_velocity(std::array<std::vector<Vec3>, gear_order>& x, std::size_t b, std::size_t e)
{
    predictor()(flat(x[0], b, e).data(), flat(x[1], b, e).data(), flat(x[2], b, e).data(),
        flat(x[3], b, e).data(), flat(x[4], b, e).data(), flat(x[5], b, e).data(), 3 * (e - b));
}

/// Corrects bodies [b, e) (at most integrate_block) with the accelerations
/// inv_mass · load (F/m, or τ/I): predicts x₂…x₅ from their values of the
/// last step and applies Δ = δt²/2 · a − x₂(predicted) to every derivative.
void correct(std::array<std::vector<Vec3>, gear_order>& x, std::size_t b, std::size_t e,
    const std::vector<double>& inv_mass, const std::vector<Vec3>& load, double half_dt2)
{
    const std::array<Vec3, integrate_block> half_a_dt2 = scaled_accelerations(b, e, inv_mass, load, half_dt2);
    corrector()(flat(x[0], b, e).data(), flat(x[1], b, e).data(), flat(x[2], b, e).data(),
        flat(x[3], b, e).data(), flat(x[4], b, e).data(), flat(x[5], b, e).data(), half_a_dt2.data()->data(),
        3 * (e - b));
}

} // namespace

void gear5_predict(World& w, ThreadPool& pool)
{
    for (auto& body : w.bodies) {
        parallel_for_blocks(pool, body.size(), integrate_block, [&](std::size_t begin, std::size_t end) {
            for_each_run(body.motion, Motion::dynamic, begin, end,
                [&](std::size_t b, std::size_t e) { predict_position_and_velocity(body.x, b, e); });
            move_kinematic(body.x, body.motion, begin, end);
        });
    }
    // Grains turn while they are dynamic (a kinematic or fixed grain does not).
    RotationalState& rot = w.grain_rotation;
    const std::vector<Motion>& grain_motion = w.of(BodyKind::grain).motion;
    parallel_for_blocks(pool, rot.orientation.size(), integrate_block, [&](std::size_t begin, std::size_t end) {
        for_each_run(grain_motion, Motion::dynamic, begin, end,
            [&](std::size_t b, std::size_t e) { predict_position_and_velocity(rot.theta, b, e); });
    });
}

bool gear5_correct(World& w, ThreadPool& pool)
{
    const double half_dt2 = 0.5 * w.dt_s * w.dt_s;
    bool finite = true;
    for (int k = 0; k < body_kind_count; ++k) {
        TranslationalState& body = w.bodies[k];
        const std::vector<Vec3>& force = w.body_force_n[k];
        const bool body_finite = reduce_blocks(
            pool, body.size(), true,
            [&](std::size_t begin, std::size_t end) {
                bool ok = true;
                for (std::size_t block = begin; block < end; block += integrate_block) {
                    for_each_run(body.motion, Motion::dynamic, block, std::min(end, block + integrate_block),
                        [&](std::size_t b, std::size_t e) {
                            correct(body.x, b, e, body.inv_mass_per_kg, force, half_dt2);
                            ok = ok && all_finite(body.x[0], b, e);
                        });
                }
                return ok;
            },
            [](bool a, bool b) { return a && b; });
        finite = finite && body_finite;
    }
    RotationalState& rot = w.grain_rotation;
    const std::vector<Motion>& grain_motion = w.of(BodyKind::grain).motion;
    parallel_for_blocks(pool, rot.orientation.size(), integrate_block, [&](std::size_t begin, std::size_t end) {
        for_each_run(grain_motion, Motion::dynamic, begin, end, [&](std::size_t b, std::size_t e) {
            correct(rot.theta, b, e, rot.inv_inertia_per_kg_m2, w.grain_torque_n_m, half_dt2);
            // q ← exp(½ ω δt) ⊗ q, with ω δt = w₁
            turn_all(rot.orientation.data() + b, rot.theta[1].data() + b, e - b);
        });
    });
    return finite;
}

} // namespace wiredem::engine
