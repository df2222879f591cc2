// Small builders shared by the engine tests.
#pragma once

#include "contact/pair_kernel_simd.hpp"
#include "scene.hpp"
#include "simulation.hpp"
#include "state/world.hpp"
#include "timestep.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wiredem::engine::test {

/// A world without gravity, one material, the given damping, δt.
inline void reset_world(World& w, const Material& m, double dt_s, double damping_s = 0.0)
{
    w = World{};
    w.gravity_m_per_s2 = Vec3::Zero();
    w.dt_s = dt_s;
    w.contact.normal_damping_s = damping_s;
    add_material(w, m);
}

} // namespace wiredem::engine::test

namespace wiredem::engine::test {

/// Dynamic relaxation towards a static equilibrium: steps the simulation and
/// removes a fraction `damping_per_step` of every body's velocity after each
/// step (critical damping of a mode ω needs ≈ 2 ω δt). Test-only: the engine
/// itself has no global damping (model spec §4).
inline void relax(Simulation& sim, std::uint64_t steps, double damping_per_step)
{
    for (std::uint64_t s = 0; s < steps; ++s) {
        sim.step();
        scale_velocities(sim.world, 1.0 - damping_per_step);
    }
}

} // namespace wiredem::engine::test

namespace wiredem::engine::test {

/// The SIMD paths this CPU can run, each once: what `automatic` picks
/// (AVX-512 or AVX2) and, on a CPU with AVX-512, the AVX2 kernels too. Leaves
/// the choice at `automatic`.
inline std::vector<SimdKernels> simd_choices()
{
    std::vector<SimdKernels> choices;
    std::vector<SimdIsa> seen;
    for (SimdKernels k : {SimdKernels::automatic, SimdKernels::avx2}) {
        set_simd_kernels(k);
        const SimdIsa isa = simd_isa();
        if (isa != SimdIsa::none && std::find(seen.begin(), seen.end(), isa) == seen.end()) {
            choices.push_back(k);
            seen.push_back(isa);
        }
    }
    set_simd_kernels(SimdKernels::automatic);
    return choices;
}

/// Puts the SIMD choice back to `automatic` when it goes out of scope.
struct RestoreSimdKernels {
    RestoreSimdKernels() = default;
    RestoreSimdKernels(const RestoreSimdKernels&) = delete;
    RestoreSimdKernels& operator=(const RestoreSimdKernels&) = delete;
    ~RestoreSimdKernels() { set_simd_kernels(SimdKernels::automatic); }
};

/// A small column of soft grains falling into a cylinder: 400 grains
/// (E = 10⁸ Pa: a large δt, the same code paths) in R = 6 mm, γ_n = 10⁻⁵ s,
/// the automatic δt, each grain kicked to `kick` · (u_x − ½, u_y − ½, −1)
/// m/s with u drawn from `kick_seed`: contacts form, slide and break.
inline void build_kicked_column(World& w, std::uint64_t seed, std::uint64_t kick_seed, double kick)
{
    ContainerSpec spec;
    spec.container_radius_m = 6e-3;
    spec.grains = 400;
    spec.grain.youngs_modulus_pa = 1e8;
    spec.seed = seed;
    build_container(w, spec);
    w.contact.normal_damping_s = 1e-5;
    w.dt_s = stable_time_step(w).auto_s;
    SplitMix64 rng(kick_seed);
    for (std::uint32_t i = 0; i < w.bodies[0].size(); ++i) {
        const double vy = rng.uniform() - 0.5; // drawn y first: one scene for every compiler (engine/scene.cpp)
        const double vx = rng.uniform() - 0.5;
        set_velocity(w, {BodyKind::grain, i}, kick * Vec3(vx, vy, -1.0));
    }
}

} // namespace wiredem::engine::test
