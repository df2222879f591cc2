// Walls see only the bodies near them (candidates rebuilt with the neighbour
// list); these tests check that no contact is missed or left behind.
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {
const Material grain_material{10e9, 0.3, 7800.0};
const Material plate_material{1e9, 0.3, 7800.0};
constexpr double radius_m = 1.23e-3;
} // namespace

TEST(Walls, ALidComingDownFromFarAwayPressesWithTheHertzForceFromItsFirstTouch)
{
    // No gravity, no damping; a grain at rest on the floor and a lid coming
    // down from 10 skins above at 0.5 m/s. On every step the lid's force on
    // the grain must be the undamped Hertz force of the lid overlap (zero
    // before touching): a lid that moved many skins between the grain's
    // rebuilds still finds it.
    Simulation sim(1);
    World& w = sim.world;
    reset_world(w, grain_material, 1e-7);
    w.integrator = Integrator::verlet; // positions at the force evaluation are the step's final ones
    const std::uint8_t plate = add_material(w, plate_material);
    add_wall(w, make_plate(0.0, +1.0, plate));
    add_grain(w, Vec3(0, 0, radius_m), radius_m, 0);
    const double skin = effective_skin_m(w);
    Wall lid = make_plate(2.0 * radius_m + 10.0 * skin, -1.0, plate);
    lid.velocity_m_per_s = Vec3(0, 0, -0.5);
    const std::size_t lid_index = add_wall(w, lid);
    w.dt_s = stable_time_step(w, 0.5).auto_s;
    const int steps = static_cast<int>(10.0 * skin / 0.5 / w.dt_s) + 2000;
    const double e_star = effective_modulus_pa(10e9, 0.3, 1e9, 0.3);
    bool touched = false;
    for (int s = 0; s < steps; ++s) {
        sim.step();
        const Wall& l = w.walls[lid_index];
        const double overlap = w.bodies[0].x[0][0].z() + radius_m - l.point_m.z();
        const double expected = overlap > 0.0 ? (4.0 / 3.0) * e_star * std::sqrt(radius_m) * std::pow(overlap, 1.5) : 0.0;
        ASSERT_NEAR(w.wall_loads[lid_index].total_force_n.z(), expected, 1e-9 * expected + 1e-12) << "step " << s;
        touched = touched || overlap > 0.0;
    }
    EXPECT_TRUE(touched);
    EXPECT_GT(w.neighbour_builds, 2u); // the lid's motion forced rebuilds
}

TEST(Walls, ABodyMovedAwayByHandLeavesNoForceBehind)
{
    // A grain pressed into the floor, then moved far away by hand: its stale
    // wall slot must not be gathered on the next step.
    Simulation sim(1);
    World& w = sim.world;
    reset_world(w, grain_material, 1e-7);
    const std::uint8_t plate = add_material(w, plate_material);
    add_wall(w, make_plate(0.0, +1.0, plate));
    add_grain(w, Vec3(0, 0, 0.99 * radius_m), radius_m, 0);
    sim.step();
    ASSERT_EQ(w.wall_loads[0].contacts, 1u);
    place_body(w, BodyRef(BodyKind::grain, 0), Vec3(0, 0, 0.1));
    sim.step();
    EXPECT_EQ(w.wall_loads[0].contacts, 0u);
    EXPECT_EQ(w.body_force_n[0][0], Vec3::Zero());
}
