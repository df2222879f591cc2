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
    for (int ms = 0; ms < 200; ++ms) {
        const RunOutcome out = sim.run(steps_per_ms);
        ASSERT_EQ(out.end, RunEnd::completed) << "at " << ms << " ms";
        ke = kinetic_energy_j(w, sim.pool());
        peak_ke = std::max(peak_ke, ke);
    }
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
    // Force balance of the settled pile: the floor carries its weight, minus
    // what friction on the cylinder holds (Janssen) — never more, and most of it.
    const double weight = mass * g.size() * 10.0;
    EXPECT_LT(w.wall_loads[0].total_force_n.z(), -0.5 * weight);
    EXPECT_GT(w.wall_loads[0].total_force_n.z(), -1.01 * weight);
}
