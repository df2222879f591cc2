// A pile of a few hundred grains settles in a cylindrical container.
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "scene.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

using namespace wiredem::engine;

TEST(Pile, SettlesWithoutEscapeOrNaNAndLosesItsKineticEnergy)
{
    Simulation sim(2);
    ContainerSpec spec;
    spec.container_radius_m = 8e-3;
    spec.grains = 200;
    spec.lattice_gap = 0.5;                // dropped from a loose lattice
    spec.grain.youngs_modulus_pa = 1e8;    // soft grains: large δt, same physics
    build_container(sim.world, spec);
    World& w = sim.world;
    const double mass = w.bodies[0].mass_kg[0];
    // e_n = 0.5 for a grain–grain impact at 0.3 m/s.
    const double e_star = effective_modulus_pa(1e8, 0.3, 1e8, 0.3);
    w.contact.normal_damping_s = hertz_damping_for_restitution_s(0.5, 0.5 * mass, 0.3, e_star, 0.5 * spec.grain_radius_m);
    w.dt_s = stable_time_step(w).auto_s;

    double peak_ke = 0.0, ke = 0.0;
    const auto steps_per_ms = static_cast<std::uint64_t>(1e-3 / w.dt_s);
    for (int ms = 0; ms < 180; ++ms) {
        const RunOutcome out = sim.run(steps_per_ms);
        ASSERT_EQ(out.end, RunEnd::completed) << "at " << ms << " ms";
        ke = kinetic_energy_j(w, sim.pool());
        peak_ke = std::max(peak_ke, ke);
    }
    // The last 20 ms a step at a time: the walls' vertical force, summed.
    const auto momentum_z = [&] {
        double p = 0.0;
        for (std::uint32_t i = 0; i < w.bodies[0].size(); ++i)
            p += w.bodies[0].mass_kg[i] * velocity_m_per_s(w, {BodyKind::grain, i}).z();
        return p;
    };
    const double p0 = momentum_z();
    double walls_impulse = 0.0; // ∫ (floor + cylinder) dt, the force the grains exert on them
    const std::uint64_t window_steps = 20 * steps_per_ms;
    for (std::uint64_t k = 0; k < window_steps; ++k) {
        ASSERT_EQ(sim.run(1).end, RunEnd::completed);
        walls_impulse += (w.wall_loads[0].total_force_n.z() + w.wall_loads[1].total_force_n.z()) * w.dt_s;
    }
    const double window_s = static_cast<double>(window_steps) * w.dt_s;
    ke = kinetic_energy_j(w, sim.pool());
    // Dropped from rest, the grains speed up and then lose it all in damped
    // collisions: by the end the kinetic energy is below 10⁻³ of its peak,
    // and nothing has left the box.
    EXPECT_GT(peak_ke, 0.0);
    EXPECT_LT(ke, 1e-3 * peak_ke);
    const auto& g = w.bodies[0];
    for (std::size_t i = 0; i < g.size(); ++i) {
        const Vec3& x = g.x[0][i];
        ASSERT_TRUE(x.allFinite());
        EXPECT_GT(x.z(), 0.9 * spec.grain_radius_m) << i;
        EXPECT_LT(std::hypot(x.x(), x.y()), spec.container_radius_m - 0.9 * spec.grain_radius_m) << i;
    }
    // Force balance of the settled pile, over the window (at one step the
    // walls' force swings with the pile's residual motion by several per cent
    // of the weight). Momentum: the grains' change of momentum is gravity's
    // impulse less the walls', Δp = −W T − ∫F dt, to the integrator's error
    // (the pair forces cancel); and the pile being at rest, Δp/T is a small
    // part of W, so the walls carry the weight, the floor most of it
    // (Janssen: friction on the cylinder holds up the rest, or, locked in
    // as the pile came to rest, may push down a little).
    const double weight = mass * g.size() * 10.0;
    const double dp = momentum_z() - p0;
    EXPECT_NEAR(dp, -weight * window_s - walls_impulse, 1e-3 * weight * window_s) << "momentum theorem";
    EXPECT_NEAR(walls_impulse / window_s, -weight, 0.01 * weight);
    EXPECT_LT(w.wall_loads[0].total_force_n.z(), -0.5 * weight);
}
