#include "integrate/verlet.hpp"

#include "contact/pair_kernel_simd.hpp"
#include "core/assert.hpp"
#include "integrate/clumps.hpp"
#include "integrate/flat_runs.hpp"
#include "integrate/rotation.hpp"
#include "parallel/body_blocks.hpp"

#include <algorithm>

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#endif

namespace wiredem::engine {
namespace {

// Velocity Verlet on scaled derivatives (x₁ = δt v, x₂ = δt²/2 a), as Gear-5's
// loops in gear5.cpp: a run of consecutive bodies' arrays as flat arrays of
// doubles, each loop one text built for AVX2 and for the baseline, with the
// Vec3 expressions' operations element by element (the same bits).

/// First half over n doubles: x₀ ← x₀ + (x₁ + x₂), x₁ ← x₁ + x₂ (the
/// half-kick with the last step's x₂, then the drift).
[[gnu::always_inline]] inline void drift_flat(
    double* __restrict x0, double* __restrict x1, const double* __restrict x2, std::size_t n)
{
    for (std::size_t j = 0; j < n; ++j) {
        x0[j] += x1[j] + x2[j];
        x1[j] += x2[j];
    }
}

/// Second half over n doubles, x₂ = δt²/2 a already set: x₁ ← x₁ + x₂.
/// Returns whether every new x₁ is finite.
[[gnu::always_inline]] inline bool kick_flat(double* __restrict x1, const double* __restrict x2, std::size_t n)
{
    std::uint64_t non_finite = 0;
    for (std::size_t j = 0; j < n; ++j) {
        x1[j] += x2[j];
        non_finite |= non_finite_bit(x1[j]);
    }
    return non_finite == 0;
}

/// A loop over n doubles of two arrays it updates and one it reads.
using FlatLoop = void (*)(double*, double*, const double*, std::size_t);
/// A loop over n doubles of an array it updates and one it reads; whether the updated values are finite.
using KickLoop = bool (*)(double*, const double*, std::size_t);

void drift_flat_baseline(double* __restrict x0, double* __restrict x1, const double* __restrict x2, std::size_t n)
{
    drift_flat(x0, x1, x2, n);
}
bool kick_flat_baseline(double* __restrict x1, const double* __restrict x2, std::size_t n)
{
    return kick_flat(x1, x2, n);
}

#if defined(__x86_64__)
[[WIREDEM_AVX2_TARGET]] void drift_flat_avx2(
    double* __restrict x0, double* __restrict x1, const double* __restrict x2, std::size_t n)
{
    drift_flat(x0, x1, x2, n);
}
[[WIREDEM_AVX2_TARGET]] bool kick_flat_avx2(double* __restrict x1, const double* __restrict x2, std::size_t n)
{
    return kick_flat(x1, x2, n);
}
#endif

/// The loops of the instruction set in use (simd_isa, as Gear-5's).
FlatLoop drifter()
{
#if defined(__x86_64__)
    if (simd_isa() != SimdIsa::none) return &drift_flat_avx2;
#endif
    return &drift_flat_baseline;
}
KickLoop kicker()
{
#if defined(__x86_64__)
    if (simd_isa() != SimdIsa::none) return &kick_flat_avx2;
#endif
    return &kick_flat_baseline;
}

/// Second half for bodies [b, e) (at most integrate_block) with the
/// accelerations inv_mass · load (F/m, or τ/I): x₂ = δt²/2 a, x₁ += x₂.
/// Returns whether every new x₁ is finite.
bool kick(std::array<std::vector<Vec3>, gear_order>& x, std::size_t b, std::size_t e,
    const std::vector<double>& inv_mass, const std::vector<Vec3>& load, double half_dt2)
{
    scale_accelerations(inv_mass.data() + b, load.data() + b, half_dt2, e - b, x[2].data() + b);
    return kicker()(flat(x[1], b, e).data(), flat(x[2], b, e).data(), 3 * (e - b));
}

} // namespace

// Both halves run on the blocks of the gather and of Gear-5 (body_blocks),
// a grain's rotation with its grain: a thread works on the bodies whose
// forces it gathered. Elementwise, so the blocks do not change a bit.

void verlet_first_half(World& w, ThreadPool& pool)
{
    const FlatLoop drift = drifter();
    // Grains turn while they are dynamic (a kinematic or fixed grain does not).
    RotationalState& rot = w.grain_rotation;
    const std::vector<Motion>& grain_motion = w.of(BodyKind::grain).motion;
    WIREDEM_ASSERT(rot.orientation.size() == grain_motion.size(), "every grain has a rotation");
    body_blocks(w, pool, [&](std::size_t k, std::size_t begin, std::size_t end) {
        TranslationalState& body = w.bodies[k];
        for_each_run(body.motion, Motion::dynamic, begin, end, [&](std::size_t b, std::size_t e) {
            drift(flat(body.x[0], b, e).data(), flat(body.x[1], b, e).data(), flat(body.x[2], b, e).data(), 3 * (e - b));
        });
        move_kinematic(body.x, body.motion, begin, end);
        if (k != static_cast<std::size_t>(BodyKind::grain)) return;
        for_each_run(grain_motion, Motion::dynamic, begin, end, [&](std::size_t b, std::size_t e) {
            flat(rot.theta[1], b, e) += flat(rot.theta[2], b, e); // w₁ += w₂
            // q ← exp(½ ω δt) ⊗ q with the half-step ω (w₁ = δt ω)
            turn_all(rot.orientation.data() + b, rot.theta[1].data() + b, e - b);
        });
    });
    verlet_first_half_clumps(w, pool); // puts their spheres, which the loop above skips
}

bool verlet_second_half(World& w, ThreadPool& pool)
{
    const double half_dt2 = 0.5 * w.dt_s * w.dt_s;
    RotationalState& rot = w.grain_rotation;
    // Whether every body's new x₀ and x₁ are finite.
    const bool finite = all_dynamic_runs(
        w, pool,
        [&](std::size_t k, std::size_t b, std::size_t e) {
            TranslationalState& body = w.bodies[k];
            return kick(body.x, b, e, body.inv_mass_per_kg, w.body_force_n[k], half_dt2) && all_finite(body.x[0], b, e);
        },
        [&](std::size_t b, std::size_t e) {
            (void)kick(rot.theta, b, e, rot.inv_inertia_per_kg_m2, w.grain_torque_n_m, half_dt2);
        });
    return verlet_second_half_clumps(w, pool) && finite;
}

} // namespace wiredem::engine
