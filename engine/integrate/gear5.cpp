#include "integrate/gear5.hpp"

#include "contact/pair_kernel_simd.hpp"
#include "core/assert.hpp"
#include "integrate/clumps.hpp"
#include "integrate/flat_runs.hpp"
#include "integrate/rotation.hpp"
#include "parallel/body_blocks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#endif

namespace wiredem::engine {
namespace {

// The prediction x_k ← Σ_{j≥k} C(j,k) x_j (Pascal triangle) is split in two:
// x₀ and x₁, the derivatives the force stages read, are predicted by the
// last step's corrector, which has every corrected derivative in registers
// and writes the two predicted ones beside them (Caches::next_prediction);
// the predictor then only swaps those arrays in. x₂…x₅ are predicted by the
// corrector itself, on the fly. Reading the six arrays once per step instead
// of twice matters: at the paper's size they stream from L3 (40 000 bodies ×
// 144 bytes). The stored derivatives between steps stay the corrected ones;
// the prediction is a cache, made with the same operations as a predictor
// reading them, so the bits are the same as without it. When a mutator has
// dropped it (a body added, moved or set moving, δt changed) or a run starts,
// the predictor reads the six arrays as before. A grain's rotation keeps no
// θ₀ (Position::without): only θ₁ is predicted and kept.
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

/// x₀ (with_position) and x₁ predicted in place, over n doubles. Without
/// the position (a grain's rotation vector θ₀, which nothing reads) x0 is not
/// touched.
template <bool with_position>
[[gnu::always_inline]] inline void predict_flat(double* __restrict x0, double* __restrict x1,
    const double* __restrict x2, const double* __restrict x3, const double* __restrict x4,
    const double* __restrict x5, std::size_t n)
{
    for (std::size_t j = 0; j < n; ++j) {
        if constexpr (with_position) x0[j] += x1[j] + x2[j] + x3[j] + x4[j] + x5[j];
        x1[j] += 2.0 * x2[j] + 3.0 * x3[j] + 4.0 * x4[j] + 5.0 * x5[j];
    }
}

/// x₂…x₅ predicted, then every derivative corrected by Δ = target − x₂(predicted),
/// and x₀, x₁ of the next step predicted from the corrected ones into next0,
/// next1 (predict_flat's operations), over n doubles. Returns whether every
/// corrected x₀ is finite. Without the position, x0 and next0 are not
/// touched (and the check is on x₁).
template <bool with_position>
[[gnu::always_inline]] inline bool correct_flat(double* __restrict x0, double* __restrict x1,
    double* __restrict x2, double* __restrict x3, double* __restrict x4, double* __restrict x5,
    const double* __restrict target, double* __restrict next0, double* __restrict next1, std::size_t n)
{
    constexpr const double* c = gear5_corrector;
    std::uint64_t non_finite = 0;
    for (std::size_t j = 0; j < n; ++j) {
        const double p2 = x2[j] + (3.0 * x3[j] + 6.0 * x4[j] + 10.0 * x5[j]);
        const double p3 = x3[j] + (4.0 * x4[j] + 10.0 * x5[j]);
        const double p4 = x4[j] + 5.0 * x5[j];
        const double delta = target[j] - p2;
        const double c1 = x1[j] + c[1] * delta;
        const double c2 = p2 + c[2] * delta;
        const double c3 = p3 + c[3] * delta;
        const double c4 = p4 + c[4] * delta;
        const double c5 = x5[j] + c[5] * delta;
        x1[j] = c1;
        x2[j] = c2;
        x3[j] = c3;
        x4[j] = c4;
        x5[j] = c5;
        next1[j] = c1 + (2.0 * c2 + 3.0 * c3 + 4.0 * c4 + 5.0 * c5);
        if constexpr (with_position) {
            const double c0 = x0[j] + c[0] * delta;
            x0[j] = c0;
            next0[j] = c0 + (c1 + c2 + c3 + c4 + c5);
            non_finite |= non_finite_bit(c0);
        } else {
            non_finite |= non_finite_bit(c1);
        }
    }
    return non_finite == 0;
}

using PredictFlat = void (*)(double*, double*, const double*, const double*, const double*, const double*, std::size_t);
using CorrectFlat = bool (*)(double*, double*, double*, double*, double*, double*, const double*, double*, double*,
    std::size_t);

template <bool with_position>
void predict_flat_baseline(double* __restrict x0, double* __restrict x1, const double* __restrict x2,
    const double* __restrict x3, const double* __restrict x4, const double* __restrict x5, std::size_t n)
{
    predict_flat<with_position>(x0, x1, x2, x3, x4, x5, n);
}
template <bool with_position>
bool correct_flat_baseline(double* __restrict x0, double* __restrict x1, double* __restrict x2,
    double* __restrict x3, double* __restrict x4, double* __restrict x5, const double* __restrict target,
    double* __restrict next0, double* __restrict next1, std::size_t n)
{
    return correct_flat<with_position>(x0, x1, x2, x3, x4, x5, target, next0, next1, n);
}
#if defined(__x86_64__)
template <bool with_position>
[[WIREDEM_AVX2_TARGET]] void predict_flat_avx2(double* __restrict x0, double* __restrict x1,
    const double* __restrict x2, const double* __restrict x3, const double* __restrict x4,
    const double* __restrict x5, std::size_t n)
{
    predict_flat<with_position>(x0, x1, x2, x3, x4, x5, n);
}
template <bool with_position>
[[WIREDEM_AVX2_TARGET]] bool correct_flat_avx2(double* __restrict x0, double* __restrict x1, double* __restrict x2,
    double* __restrict x3, double* __restrict x4, double* __restrict x5, const double* __restrict target,
    double* __restrict next0, double* __restrict next1, std::size_t n)
{
    return correct_flat<with_position>(x0, x1, x2, x3, x4, x5, target, next0, next1, n);
}
#endif

/// The predictor and corrector loops of the instruction set in use.
template <bool with_position>
PredictFlat predictor()
{
#if defined(__x86_64__)
    if (simd_isa() != SimdIsa::none) return &predict_flat_avx2<with_position>;
#endif
    return &predict_flat_baseline<with_position>;
}
template <bool with_position>
CorrectFlat corrector()
{
#if defined(__x86_64__)
    if (simd_isa() != SimdIsa::none) return &correct_flat_avx2<with_position>;
#endif
    return &correct_flat_baseline<with_position>;
}

/// Bodies have a position x₀; a grain's rotation has none that anything
/// reads (θ₀ would sum rotation vectors, which is no angle in 3D: the
/// orientation quaternion is the grain's attitude), so θ₀ is not integrated.
enum class Position : bool { without, with };

using Derivatives = std::array<std::vector<Vec3>, gear_order>;
using Prediction = std::array<std::vector<Vec3>, 2>;

/// Predicts x₀ (with a position) and x₁ of bodies [b, e) in place from the derivative arrays.
template <Position position>
void predict_position_and_velocity(Derivatives& x, std::size_t b, std::size_t e)
{
    constexpr bool p = position == Position::with;
    predictor<p>()(p ? flat(x[0], b, e).data() : nullptr, flat(x[1], b, e).data(), flat(x[2], b, e).data(),
        flat(x[3], b, e).data(), flat(x[4], b, e).data(), flat(x[5], b, e).data(), 3 * (e - b));
}

/// Corrects bodies [b, e) (at most integrate_block) with the accelerations
/// inv_mass · load (F/m, or τ/I): predicts x₂…x₅ from their values of the
/// last step and applies Δ = δt²/2 · a − x₂(predicted) to every derivative;
/// then predicts x₀ (with a position) and x₁ of the next step into `next`.
/// Returns whether every corrected x₀ (without a position: x₁) is finite.
template <Position position>
bool correct(Derivatives& x, Prediction& next, std::size_t b, std::size_t e, const std::vector<double>& inv_mass,
    const std::vector<Vec3>& load, double half_dt2)
{
    constexpr bool p = position == Position::with;
    const std::array<Vec3, integrate_block> half_a_dt2 = scaled_accelerations(b, e, inv_mass, load, half_dt2);
    return corrector<p>()(p ? flat(x[0], b, e).data() : nullptr, flat(x[1], b, e).data(), flat(x[2], b, e).data(),
        flat(x[3], b, e).data(), flat(x[4], b, e).data(), flat(x[5], b, e).data(), half_a_dt2.data()->data(),
        p ? flat(next[0], b, e).data() : nullptr, flat(next[1], b, e).data(), 3 * (e - b));
}

/// Whether `next` holds a prediction of n bodies.
template <Position position>
bool sized_for(const Prediction& next, std::size_t n)
{
    return (position == Position::without || next[0].size() == n) && next[1].size() == n;
}

/// The kept prediction made x₀ and x₁: the arrays swap, and the bodies that
/// are kinematic or fixed, which the corrector skipped, take their stored
/// values (which `next` now holds) over [begin, end); with a position, the
/// kinematic ones then move (move_kinematic_body). One scan of the
/// motions finds whether the range has any such body (usually none), one
/// loop takes and moves them. A clump's spheres take nothing:
/// gear5_predict_clumps puts them at the end of the predictor.
template <Position position>
void take_kept(Derivatives& x, const Prediction& stored, const std::vector<Motion>& motion, std::size_t begin,
    std::size_t end)
{
    if (!any_prescribed(motion, begin, end)) return;
    for (std::size_t i = begin; i < end; ++i)
        if (is_prescribed(motion[i])) {
            x[1][i] = stored[1][i];
            if constexpr (position == Position::with) {
                x[0][i] = stored[0][i];
                if (motion[i] == Motion::kinematic) move_kinematic_body(x, i);
            }
        }
}

#if defined(WIREDEM_CHECK_PREDICTION)
/// The sanitizer builds check every kept prediction against predict_flat's
/// operations on the stored derivatives, bit for bit: a body changed between
/// steps by something other than a mutator would step from a stale one.
template <Position position>
void check_kept(const Derivatives& x, const Prediction& stored, const std::vector<Motion>& motion, const char* what)
{
    for (std::size_t i = 0; i < motion.size(); ++i) {
        if (motion[i] != Motion::dynamic) continue;
        const Vec3 p0 = position == Position::with
                          ? Vec3(stored[0][i] + (stored[1][i] + x[2][i] + x[3][i] + x[4][i] + x[5][i]))
                          : x[0][i];
        const Vec3 p1 = stored[1][i] + (2.0 * x[2][i] + 3.0 * x[3][i] + 4.0 * x[4][i] + 5.0 * x[5][i]);
        // A NaN's payload may depend on the operand order, which vector code chooses.
        const auto same = [](const Vec3& a, const Vec3& b) {
            return std::memcmp(a.data(), b.data(), sizeof(Vec3)) == 0 || (a.hasNaN() && b.hasNaN());
        };
        if (!same(p0, x[0][i]) || !same(p1, x[1][i])) {
            std::fprintf(stderr, "gear5_predict: the kept prediction of %s %zu is stale: it was changed between "
                                 "steps without a mutator (state/world.hpp)\n", what, i);
            std::abort();
        }
    }
}
#endif

} // namespace

// The predictor and the corrector each run every kind of body and the
// grains' rotations in one parallel loop, on the blocks of the gather
// (body_blocks), a grain's rotation with its grain: at the paper's size
// each kind's loop is a few tens of microseconds, and four loops with a
// join each cost the second thread most of its share; and a thread works
// on the bodies whose forces it gathered. Elementwise, so the blocks a body
// is in do not change its bits.

void gear5_predict(World& w, ThreadPool& pool)
{
    GearPrediction& next = w.next_prediction;
    const bool kept = next.for_step == w.step_count;
    next.for_step = GearPrediction::none; // used up: this step's corrector makes the next one
    std::array<bool, body_kind_count> take{};
    for (int k = 0; k < body_kind_count; ++k) {
        TranslationalState& body = w.bodies[k];
        Prediction& stored = next.x[k];
        // A kind without a dynamic body (a rigid membrane: all fixed) has no
        // prediction to take; swapping would only copy all its bodies back.
        take[k] = kept && sized_for<Position::with>(stored, body.size())
               && any_of_motion(body.motion, Motion::dynamic, 0, body.size());
        if (take[k]) std::swap(body.x[0], stored[0]), std::swap(body.x[1], stored[1]);
    }
    // Grains turn while they are dynamic (a kinematic or fixed grain does not).
    RotationalState& rot = w.grain_rotation;
    const std::vector<Motion>& grain_motion = w.of(BodyKind::grain).motion;
    WIREDEM_ASSERT(rot.orientation.size() == grain_motion.size(), "every grain has a rotation");
    const bool take_rotation = kept && sized_for<Position::without>(next.theta, rot.orientation.size())
                            && any_of_motion(grain_motion, Motion::dynamic, 0, grain_motion.size());
    if (take_rotation) std::swap(rot.theta[1], next.theta[1]);
    body_blocks(w, pool, [&](std::size_t k, std::size_t begin, std::size_t end) {
        TranslationalState& body = w.bodies[k];
        if (take[k]) {
            take_kept<Position::with>(body.x, next.x[k], body.motion, begin, end);
        } else {
            for_each_run(body.motion, Motion::dynamic, begin, end, [&](std::size_t b, std::size_t e) {
                predict_position_and_velocity<Position::with>(body.x, b, e);
            });
            move_kinematic(body.x, body.motion, begin, end);
        }
        if (k != static_cast<std::size_t>(BodyKind::grain)) return;
        if (take_rotation) {
            take_kept<Position::without>(rot.theta, next.theta, grain_motion, begin, end);
        } else {
            for_each_run(grain_motion, Motion::dynamic, begin, end, [&](std::size_t b, std::size_t e) {
                predict_position_and_velocity<Position::without>(rot.theta, b, e);
            });
        }
    });
#if defined(WIREDEM_CHECK_PREDICTION)
    for (int k = 0; k < body_kind_count; ++k)
        if (take[k]) check_kept<Position::with>(w.bodies[k].x, next.x[k], w.bodies[k].motion, "body");
    if (take_rotation) check_kept<Position::without>(rot.theta, next.theta, grain_motion, "the rotation of grain");
#endif
    gear5_predict_clumps(w, pool); // puts their spheres, which the loops above skip
}

bool gear5_correct(World& w, ThreadPool& pool)
{
    const double half_dt2 = 0.5 * w.dt_s * w.dt_s;
    GearPrediction& next = w.next_prediction;
    for (int k = 0; k < body_kind_count; ++k)
        for (auto& v : next.x[k]) v.resize(w.bodies[k].size());
    RotationalState& rot = w.grain_rotation;
    next.theta[1].resize(rot.orientation.size()); // θ₀ is not integrated
    // Whether every corrected position is finite.
    const bool finite = all_dynamic_runs(
        w, pool,
        [&](std::size_t k, std::size_t b, std::size_t e) {
            TranslationalState& body = w.bodies[k];
            return correct<Position::with>(body.x, next.x[k], b, e, body.inv_mass_per_kg, w.body_force_n[k], half_dt2);
        },
        [&](std::size_t b, std::size_t e) {
            (void)correct<Position::without>(
                rot.theta, next.theta, b, e, rot.inv_inertia_per_kg_m2, w.grain_torque_n_m, half_dt2);
            // q ← exp(½ ω δt) ⊗ q, with ω δt = w₁
            turn_all(rot.orientation.data() + b, rot.theta[1].data() + b, e - b);
        });
    const bool clumps_finite = gear5_correct_clumps(w, pool);
    next.for_step = w.step_count + 1; // step() counts this step after the corrector
    return finite && clumps_finite;
}

} // namespace wiredem::engine
