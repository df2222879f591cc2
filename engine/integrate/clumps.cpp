#include "integrate/clumps.hpp"

#include "contact/pair_kernel_simd.hpp"
#include "integrate/clump_simd.hpp"
#include "integrate/flat_runs.hpp"
#include "integrate/gear5.hpp"
#include "integrate/rotation.hpp"

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#include "contact/avx512.hpp"
#endif

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>

namespace wiredem::engine {
namespace {

/// Clumps per block of the clump passes' parallel loops. A block runs the
/// derivative updates, which are elementwise, as flat loops over its
/// clumps' arrays (integrate/flat_runs.hpp: a run of Vec3 as one array of
/// doubles), and the loads, kicks, turns and placements several clumps at a
/// time in SIMD lanes (integrate/clump_simd.hpp): every clump gets the
/// operations it got one clump per task before (until 2026-12-07), in the
/// same order, so the bits are the same for any block size, number of
/// threads and instruction set.
constexpr std::size_t clump_block = 64;

/// x_k ← Σ_{j≥k} C(j,k) x_j for k ≥ first (Gear's predictor) over n doubles
/// of the derivative arrays: the in-place Taylor shift (pass p adds x_{j+1}
/// to x_j for j ≥ p, from the top down), skipping the derivatives below
/// `first` (ω_b has no θ₀; x0 is then not touched).
template <int first>
[[gnu::always_inline]] inline void shift_loop(double* __restrict x0, double* __restrict x1, double* __restrict x2,
    double* __restrict x3, double* __restrict x4, const double* __restrict x5, std::size_t n)
{
    for (std::size_t e = 0; e < n; ++e) {
        double v[gear_order] = {first == 0 ? x0[e] : 0.0, x1[e], x2[e], x3[e], x4[e], x5[e]};
        for (int pass = 0; pass < gear_order - 1; ++pass)
            for (int j = gear_order - 2; j >= std::max(pass, first); --j) v[j] += v[j + 1];
        if constexpr (first == 0) x0[e] = v[0];
        x1[e] = v[1];
        x2[e] = v[2];
        x3[e] = v[3];
        x4[e] = v[4];
    }
}

/// Applies Δ = target − x₂ to every derivative k ≥ first with Gear-5's
/// coefficients, x_k ← x_k + c_k Δ, over n doubles.
template <int first>
[[gnu::always_inline]] inline void correct_loop(double* __restrict x0, double* __restrict x1, double* __restrict x2,
    double* __restrict x3, double* __restrict x4, double* __restrict x5, const double* __restrict target,
    std::size_t n)
{
    constexpr const double* c = gear5_corrector;
    for (std::size_t e = 0; e < n; ++e) {
        const double delta = target[e] - x2[e];
        if constexpr (first == 0) x0[e] += c[0] * delta;
        x1[e] += c[1] * delta;
        x2[e] += c[2] * delta;
        x3[e] += c[3] * delta;
        x4[e] += c[4] * delta;
        x5[e] += c[5] * delta;
    }
}

/// Verlet's first-half updates over n doubles: x₀ += x₁ + x₂, x₁ += x₂ (the
/// centre), w₁ += w₂ (L_b += δt/2 τ_b).
[[gnu::always_inline]] inline void drift_loop(double* __restrict x0, double* __restrict x1, const double* __restrict x2,
    double* __restrict w1, const double* __restrict w2, std::size_t n)
{
    for (std::size_t e = 0; e < n; ++e) {
        x0[e] += x1[e] + x2[e];
        x1[e] += x2[e];
        w1[e] += w2[e];
    }
}

/// Verlet's second-half updates over n doubles: x₁ += x₂, w₁ += w₂.
[[gnu::always_inline]] inline void kick_loop(double* __restrict x1, const double* __restrict x2, double* __restrict w1,
    const double* __restrict w2, std::size_t n)
{
    for (std::size_t e = 0; e < n; ++e) {
        x1[e] += x2[e];
        w1[e] += w2[e];
    }
}

using ShiftLoop = void (*)(double*, double*, double*, double*, double*, const double*, std::size_t);
using CorrectLoop = void (*)(double*, double*, double*, double*, double*, double*, const double*, std::size_t);
using DriftLoop = void (*)(double*, double*, const double*, double*, const double*, std::size_t);
using KickLoop = void (*)(double*, const double*, double*, const double*, std::size_t);

/// The loops, built for the baseline (SSE2), AVX2 and AVX-512 from one text,
/// as gear5.cpp's: no fused multiply–add in any (-ffp-contract=off), so all
/// give the same bits. (A block's arrays stay in L1, where AVX-512's eight
/// doubles per instruction pay; gear5.cpp's bodies stream from L3.)
struct ClumpLoops {
    ShiftLoop shift_x, shift_omega;
    CorrectLoop correct_x, correct_omega;
    DriftLoop drift;
    KickLoop kick;
};

#define WIREDEM_CLUMP_LOOPS(suffix, attributes)                                                                   \
    template <int first>                                                                                          \
    attributes void shift_##suffix(double* __restrict x0, double* __restrict x1, double* __restrict x2,            \
        double* __restrict x3, double* __restrict x4, const double* __restrict x5, std::size_t n)                  \
    {                                                                                                             \
        shift_loop<first>(x0, x1, x2, x3, x4, x5, n);                                                             \
    }                                                                                                             \
    template <int first>                                                                                          \
    attributes void correct_##suffix(double* __restrict x0, double* __restrict x1, double* __restrict x2,          \
        double* __restrict x3, double* __restrict x4, double* __restrict x5, const double* __restrict target,      \
        std::size_t n)                                                                                            \
    {                                                                                                             \
        correct_loop<first>(x0, x1, x2, x3, x4, x5, target, n);                                                   \
    }                                                                                                             \
    attributes void drift_##suffix(double* __restrict x0, double* __restrict x1, const double* __restrict x2,      \
        double* __restrict w1, const double* __restrict w2, std::size_t n)                                         \
    {                                                                                                             \
        drift_loop(x0, x1, x2, w1, w2, n);                                                                        \
    }                                                                                                             \
    attributes void kick_##suffix(double* __restrict x1, const double* __restrict x2, double* __restrict w1,       \
        const double* __restrict w2, std::size_t n)                                                               \
    {                                                                                                             \
        kick_loop(x1, x2, w1, w2, n);                                                                             \
    }                                                                                                             \
    constexpr ClumpLoops clump_loops_##suffix{&shift_##suffix<0>, &shift_##suffix<1>, &correct_##suffix<0>,      \
        &correct_##suffix<1>, &drift_##suffix, &kick_##suffix};

WIREDEM_CLUMP_LOOPS(baseline, )
#if defined(__x86_64__)
WIREDEM_CLUMP_LOOPS(avx2, [[WIREDEM_AVX2_TARGET]])
WIREDEM_CLUMP_LOOPS(avx512, [[WIREDEM_AVX512_TARGET]])
#endif
#undef WIREDEM_CLUMP_LOOPS

/// The loops of the instruction set in use (simd_isa(): `--simd scalar` takes the baseline's).
const ClumpLoops& clump_loops()
{
#if defined(__x86_64__)
    if (simd_isa() == SimdIsa::avx512) return clump_loops_avx512;
    if (simd_isa() != SimdIsa::none) return clump_loops_avx2;
#endif
    return clump_loops_baseline;
}

/// Order k of derivative set x, clumps [b, e), as flat doubles.
double* at(std::array<std::vector<Vec3>, gear_order>& x, int k, std::size_t b)
{
    return x[static_cast<std::size_t>(k)][b].data();
}

/// Gear's predictor on clumps [b, e): every derivative of the centre, and
/// ω_b's from w₁ up.
void predict_block(const ClumpLoops& loops, ClumpState& c, std::size_t b, std::size_t e)
{
    const std::size_t n = 3 * (e - b);
    loops.shift_x(at(c.x, 0, b), at(c.x, 1, b), at(c.x, 2, b), at(c.x, 3, b), at(c.x, 4, b), at(c.x, 5, b), n);
    loops.shift_omega(nullptr, at(c.omega, 1, b), at(c.omega, 2, b), at(c.omega, 3, b), at(c.omega, 4, b),
        at(c.omega, 5, b), n);
}

/// What place_clumps needs to put the spheres of w's clumps at `orientation`,
/// taking the lever arms from `arms_in` (null: turning the offsets) and
/// writing them to `arms_out` (null: nowhere).
ClumpPlacement placement(World& w, const Quat* orientation, const Vec3* arms_in, Vec3* arms_out)
{
    ClumpState& c = w.clumps;
    TranslationalState& grains = w.of(BodyKind::grain);
    return {orientation, c.x[0].data(), c.x[1].data(), c.omega[1].data(), c.first_member.data(),
        c.member_count.data(), c.member_offset_m.data(), arms_in, arms_out, grains.x[0].data(), grains.x[1].data(),
        w.grain_rotation.theta[1].data()};
}

/// What clump_kicks needs for w's clumps, with the lever arms `arms` (null:
/// turned from the offsets by `orientation`).
ClumpLoadSums load_sums(World& w, const Quat* orientation, const Vec3* arms)
{
    ClumpState& c = w.clumps;
    return {w.force_of(BodyKind::grain).data(), w.grain_torque_n_m.data(), arms, c.member_offset_m.data(), orientation,
        c.first_member.data(), c.member_count.data(), c.mass_kg.data(), w.gravity_m_per_s2,
        w.gravity_acts[static_cast<int>(BodyKind::grain)], w.clump_loads.force_n.data(), w.clump_loads.torque_n_m.data()};
}

/// The derivative arrays w₀ … w₅ of ω_b.
std::array<const Vec3*, gear_order> omega_arrays(const ClumpState& c)
{
    std::array<const Vec3*, gear_order> w{};
    for (int k = 0; k < gear_order; ++k) w[static_cast<std::size_t>(k)] = c.omega[static_cast<std::size_t>(k)].data();
    return w;
}

/// The lever arms' scratch (ClumpLoads::member_arm_m), one per grain, for a
/// first half to fill and its second half to read.
Vec3* clump_arms(World& w)
{
    std::vector<Vec3>& arms = w.clump_loads.member_arm_m;
    arms.resize(w.of(BodyKind::grain).size());
    return arms.data();
}

/// Whether clumps [b, e) have a finite centre, velocity and spin.
bool finite(const ClumpState& c, std::size_t b, std::size_t e)
{
    return all_finite(c.x[0], b, e) && all_finite(c.x[1], b, e) && all_finite(c.omega[1], b, e);
}

} // namespace

void gear5_predict_clumps(World& w, ThreadPool& pool)
{
    ClumpState& c = w.clumps;
    if (c.empty()) return;
    Quat* predicted = w.clump_loads.predicted_orientation.data();
    const ClumpPlacement put = placement(w, predicted, nullptr, clump_arms(w));
    const ClumpLoops& loops = clump_loops();
    const auto omega = omega_arrays(c);
    parallel_for_blocks(pool, c.size(), clump_block, [&](std::size_t b, std::size_t e) {
        std::array<Vec3, clump_block> turn; // from the derivatives before the prediction
        gear_turns(omega.data(), true, b, e, turn.data());
        predict_block(loops, c, b, e);
        turn_clumps(c.orientation.data() + b, turn.data(), predicted + b, e - b);
        place_clumps(put, b, e);
    });
}

bool gear5_correct_clumps(World& w, ThreadPool& pool)
{
    ClumpState& c = w.clumps;
    if (c.empty()) return true;
    std::atomic<bool> finite_all{true}; // an and, in no order
    // The predictor's lever arms, at the predicted orientation.
    const ClumpLoadSums sums = load_sums(w, w.clump_loads.predicted_orientation.data(), w.clump_loads.member_arm_m.data());
    // δt²/2 ω̇_b = δt²/2 I⁻¹ τ_b − ½ I⁻¹ (w₁ × I w₁), from the predicted w₁.
    const ClumpKick kick{w.clump_loads.predicted_orientation.data(), c.principal_inertia_kg_m2.data(), c.omega[1].data(),
        0.5 * w.dt_s * w.dt_s, true};
    const ClumpPlacement put = placement(w, c.orientation.data(), nullptr, nullptr);
    const ClumpLoops& loops = clump_loops();
    const auto omega = omega_arrays(c);
    parallel_for_blocks(pool, c.size(), clump_block, [&](std::size_t b, std::size_t e) {
        const std::size_t n = 3 * (e - b);
        std::array<Vec3, clump_block> target_x, target_omega;
        clump_kicks(sums, kick, b, e, target_x.data(), target_omega.data());
        loops.correct_x(at(c.x, 0, b), at(c.x, 1, b), at(c.x, 2, b), at(c.x, 3, b), at(c.x, 4, b), at(c.x, 5, b),
            target_x.data()->data(), n);
        loops.correct_omega(nullptr, at(c.omega, 1, b), at(c.omega, 2, b), at(c.omega, 3, b), at(c.omega, 4, b),
            at(c.omega, 5, b), target_omega.data()->data(), n);
        std::array<Vec3, clump_block> turn; // backwards from the corrected derivatives
        gear_turns(omega.data(), false, b, e, turn.data());
        turn_clumps(c.orientation.data() + b, turn.data(), c.orientation.data() + b, e - b);
        place_clumps(put, b, e);
        if (!finite(c, b, e)) finite_all.store(false, std::memory_order_relaxed);
    });
    return finite_all.load();
}

void verlet_first_half_clumps(World& w, ThreadPool& pool)
{
    ClumpState& c = w.clumps;
    if (c.empty()) return;
    const ClumpPlacement put = placement(w, c.orientation.data(), nullptr, clump_arms(w));
    const ClumpLoops& loops = clump_loops();
    parallel_for_blocks(pool, c.size(), clump_block, [&](std::size_t b, std::size_t e) {
        // The bodies' drift_flat, x₀ += x₁ + x₂; x₁ += x₂; and L_b += δt/2 τ_b.
        loops.drift(at(c.x, 0, b), at(c.x, 1, b), at(c.x, 2, b), at(c.omega, 1, b), at(c.omega, 2, b), 3 * (e - b));
        free_rotations(c.orientation.data() + b, c.omega[1].data() + b, c.principal_inertia_kg_m2.data() + b, e - b);
        place_clumps(put, b, e);
    });
}

bool verlet_second_half_clumps(World& w, ThreadPool& pool)
{
    ClumpState& c = w.clumps;
    if (c.empty()) return true;
    std::atomic<bool> finite_all{true}; // an and, in no order
    // The first half's lever arms, at the same orientation.
    const Vec3* arms = w.clump_loads.member_arm_m.data();
    const ClumpLoadSums sums = load_sums(w, c.orientation.data(), arms);
    const ClumpKick kick{c.orientation.data(), c.principal_inertia_kg_m2.data(), c.omega[1].data(), 0.5 * w.dt_s * w.dt_s, false};
    const ClumpPlacement put = placement(w, c.orientation.data(), arms, nullptr);
    const ClumpLoops& loops = clump_loops();
    parallel_for_blocks(pool, c.size(), clump_block, [&](std::size_t b, std::size_t e) {
        // x₂ = δt²/2 F/M, x₁ += x₂; w₂ = δt²/2 I⁻¹ τ_b, w₁ += w₂.
        clump_kicks(sums, kick, b, e, &c.x[2][b], &c.omega[2][b]);
        loops.kick(at(c.x, 1, b), at(c.x, 2, b), at(c.omega, 1, b), at(c.omega, 2, b), 3 * (e - b));
        if (!finite(c, b, e)) finite_all.store(false, std::memory_order_relaxed);
        place_clumps(put, b, e);
    });
    return finite_all.load();
}

void clump_initial_accelerations(World& w, ThreadPool& pool)
{
    ClumpState& c = w.clumps;
    if (c.empty()) return;
    const ClumpLoadSums sums = load_sums(w, c.orientation.data(), nullptr); // the arms turned from the offsets
    // Gear-5: δt²/2 ω̇_b with the gyroscopic term; Verlet: δt²/2 I⁻¹ τ_b.
    const ClumpKick kick{c.orientation.data(), c.principal_inertia_kg_m2.data(), c.omega[1].data(), 0.5 * w.dt_s * w.dt_s,
        w.integrator == Integrator::gear5};
    parallel_for_blocks(pool, c.size(), clump_block,
        [&](std::size_t b, std::size_t e) { clump_kicks(sums, kick, b, e, &c.x[2][b], &c.omega[2][b]); });
}

double clump_kinetic_energy_j(const State& s, std::size_t i)
{
    const ClumpState& c = s.clumps;
    const double inv_dt2 = 1.0 / (s.dt_s * s.dt_s);
    const Vec3& w1 = c.omega[1][i];
    return 0.5 * inv_dt2 * (c.mass_kg[i] * c.x[1][i].squaredNorm() + c.principal_inertia_kg_m2[i].dot(w1.cwiseProduct(w1)));
}

double clump_kinetic_energy_j(const State& s)
{
    double e = 0.0;
    for (std::size_t i = 0; i < s.clumps.size(); ++i) e += clump_kinetic_energy_j(s, i);
    return e;
}

} // namespace wiredem::engine
