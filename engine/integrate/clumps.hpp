// The rigid-body motion of clumps (state/clump_state.hpp) in both
// integrators. The integrators of the bodies call these at the end of their
// own passes, so a step's stages are unchanged; with no clump they do nothing
// (no array is touched: a World without clumps steps bit for bit as before).
//
// Loads. A clump's force is its spheres' forces (contacts and point loads;
// they weigh nothing) plus M g; its torque about the centre of mass,
// Σ (q b_i) × f_i + τ_i, with q b_i the sphere's lever arm at the
// orientation the forces were evaluated at. Summed in sphere order, each
// clump by one thread: the same bits on any number of threads.
//
// The passes run in blocks of clumps (parallel_for_blocks): the derivative
// updates as flat loops over a block's arrays, the loads, kicks, turns and the
// spheres' placement several clumps per SIMD instruction where the CPU has
// AVX2 or AVX-512 (integrate/clump_simd.hpp), each lane with the scalar
// code's operations in Eigen's order: the same bits as `--simd scalar`.
//
// Translation: the centre of mass moves as a body of mass M (Gear-5's
// predictor–corrector, Verlet's kicks and drift, on the same scaled
// derivatives as every body).
//
// Rotation, with the full inertia tensor: Euler's equations in the principal
// body frame, I ω̇_b = τ_b − ω_b × I ω_b, τ_b = q⁻¹ τ.
//  * Gear-5 integrates ω_b with the same predictor–corrector (the gyroscopic
//    term from the predicted ω_b, as velocity-dependent forces are). The
//    orientation turns as q ← q ⊗ exp(Ω) with Ω the rotation vector of the
//    step from the Magnus expansion of q̇ = ½ q ⊗ ω_b: Ω = ∫ω_b dt + (δt³/12)
//    ω_b × ω̇_b + O(δt⁵); the integral from the scaled derivatives (forwards
//    from t for the prediction, backwards from t + δt for the correction).
//  * Verlet kicks the angular momentum, L_b += (δt/2) τ_b (exactly the space
//    frame's L += (δt/2) τ), and drifts by the free rotation split along the
//    principal axes (Dullweber, Leimkuhler & McLachlan, J. Chem. Phys. 107,
//    1997: ½ about axis 3, ½ about 2, 1 about 1, ½ about 2, ½ about 3, each an
//    exact rotation of q and L_b): symplectic and time-reversible, it keeps
//    |L| and, without torque, L in space exactly up to rounding.
#pragma once

#include "parallel/thread_pool.hpp"
#include "state/world.hpp"

namespace wiredem::engine {

/// Gear-5 predictor for the clumps: every scaled derivative of the centre
/// and of ω_b predicted (Pascal triangle), the predicted orientation into
/// Caches::clump_loads, and the spheres put there.
void gear5_predict_clumps(World& w, ThreadPool& pool);

/// Gear-5 corrector for the clumps, from the spheres' gathered forces:
/// corrects both derivative sets, turns the orientation, puts the spheres at
/// the new state. Returns false if a centre or spin became non-finite.
[[nodiscard]] bool gear5_correct_clumps(World& w, ThreadPool& pool);

/// Verlet's first half for the clumps: half kick of the momenta with the
/// last loads, drift of the centre, free rotation; spheres put there.
void verlet_first_half_clumps(World& w, ThreadPool& pool);

/// Verlet's second half for the clumps: loads, half kick; spheres' velocities
/// and spins updated. Returns false if a centre or spin became non-finite.
[[nodiscard]] bool verlet_second_half_clumps(World& w, ThreadPool& pool);

/// begin_run's part for the clumps: the second derivatives from the loads at
/// the current state (Gear-5: δt²/2 ω̇_b with the gyroscopic term; Verlet:
/// δt²/2 I⁻¹ τ_b).
void clump_initial_accelerations(World& w, ThreadPool& pool);

/// Translational and rotational kinetic energy of clump `i` [J].
[[nodiscard]] double clump_kinetic_energy_j(const State& s, std::size_t i);

/// Translational and rotational kinetic energy of the clumps [J].
[[nodiscard]] double clump_kinetic_energy_j(const State& s);

} // namespace wiredem::engine
