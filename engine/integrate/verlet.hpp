// Velocity Verlet (the model spec §4: the cheaper, symplectic alternative to
// Gear-5), written on the same scaled derivatives the Gear scheme keeps:
// x₁ = δt v and x₂ = δt²/2 · a, so a World can switch integrators between runs.
//
//   first half  (before the forces):  x₀ += x₁ + x₂   (x += v δt + a δt²/2)
//                                     x₁ += x₂        (v += a δt/2)
//   second half (after the forces):   x₂ = δt²/2 · F/m
//                                     x₁ += x₂        (v += a δt/2)
//
// Velocity-dependent forces (contact damping, sliding) see the half-step
// velocity v(t + δt/2), as in LIGGGHTS and most DEM codes. Rotations use the
// same two half kicks on w₁ = δt ω; the orientation turns by the half-step ω.
// It reads and writes three derivatives per degree of freedom instead of six,
// twice per step, and on a linear oscillator it is stable up to ω δt = 2.
#pragma once

#include "parallel/thread_pool.hpp"
#include "state/world.hpp"

namespace wiredem::engine {

/// Drift and first half kick of every moving body; turns the grains.
void verlet_first_half(World& w, ThreadPool& pool);

/// Second half kick from the forces just computed. Returns false if a
/// position or velocity became non-finite.
[[nodiscard]] bool verlet_second_half(World& w, ThreadPool& pool);

} // namespace wiredem::engine
