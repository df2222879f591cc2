// begin_run (engine/step.hpp): the forces of the initial state, for Gear-5's
// first acceleration, evaluated without advancing the contacts' springs and
// sliding flags (MemoryUpdate::keep), which integrate a step's motion; what
// depends on the positions alone (releasing a contact that is apart, the
// wire joints' yield) is applied as in any evaluation.
#include "helpers.hpp"
#include "state/state_hash.hpp"
#include "step.hpp"
#include "timestep.hpp"
#include "wired_column.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

/// Bitwise equality of two springs (the memory a contact carries).
bool same_bits(const TangentialState& a, const TangentialState& b)
{
    return std::memcmp(a.spring_m.data(), b.spring_m.data(), sizeof(double) * 3) == 0 && a.sticking == b.sticking;
}

} // namespace

TEST(BeginRun, EvaluatesAColumnMidTestWithoutAdvancingItsSprings)
{
    // The wired column after 900 steps: grains sliding and sticking, wall
    // contacts, a wire ring bent beyond its joints' yield angle.
    Simulation sim(2);
    World& w = sim.world;
    build_wired_column(w, Integrator::gear5);
    for (int s = 0; s < 900; ++s) sim.step();

    // The test means something only if committing would move the springs.
    const std::vector<TangentialState> springs = w.contacts.tangential;
    World committed = w;
    evaluate_forces(committed, sim.pool(), MemoryUpdate::commit);
    std::size_t moved = 0;
    for (std::size_t p = 0; p < springs.size(); ++p) moved += !same_bits(committed.contacts.tangential[p], springs[p]);
    EXPECT_GT(moved, 10u) << "a committing evaluation advances the springs";

    begin_run(w, sim.pool());
    ASSERT_EQ(w.contacts.size(), springs.size()) << "no rebuild between the two";
    for (std::size_t p = 0; p < springs.size(); ++p) {
        // Touching or not as the positions say, like a committing evaluation.
        EXPECT_EQ(w.contacts.touching[p], committed.contacts.touching[p]) << "contact " << p;
        if (w.contacts.touching[p]) {
            EXPECT_TRUE(same_bits(w.contacts.tangential[p], springs[p])) << "contact " << p;
        } else {
            EXPECT_TRUE(same_bits(w.contacts.tangential[p], TangentialState{})) << "contact " << p << " apart: released";
        }
    }
    // The joints' yield depends on the positions alone: as committed.
    EXPECT_EQ(w.wire_rest_angle_rad, committed.wire_rest_angle_rad);
    // The forces are the committing evaluation's, bit for bit.
    for (int k = 0; k < body_kind_count; ++k) EXPECT_EQ(w.body_force_n[k], committed.body_force_n[k]) << "kind " << k;
    EXPECT_EQ(w.grain_torque_n_m, committed.grain_torque_n_m);
    EXPECT_EQ(w.wall_loads[1].total_force_n, committed.wall_loads[1].total_force_n);

    // Evaluating again changes nothing: begin_run advances no memory.
    const std::uint64_t once = state_hash(w);
    begin_run(w, sim.pool());
    EXPECT_EQ(state_hash(w), once);
    evaluate_forces(committed, sim.pool(), MemoryUpdate::commit);
    EXPECT_NE(state_hash(committed), once) << "while a second committing evaluation advances the springs again";
}

TEST(BeginRun, AContactApartIsReleasedNotLeftWithItsOldSpring)
{
    // A grain pressed on the floor and sheared (a loaded spring), then set
    // just off it, still listed: begin_run releases the contact, so a new
    // touch starts with a fresh spring.
    Simulation sim(1);
    World& w = sim.world;
    const Material grain{10e9, 0.3, 7800.0};
    reset_world(w, grain, 1e-7, 1e-5);
    add_wall(w, make_plate(0.0, +1.0, 0));
    const double r = 1.23e-3;
    add_grain(w, Vec3(0, 0, r), r, 0);
    w.grain_rotation.inv_inertia_per_kg_m2[0] = 0.0; // no rolling: the spring takes the shear
    w.point_loads.set(BodyRef(BodyKind::grain, 0), Vec3(0.05, 0.0, -1.0));
    set_time_step(w, stable_time_step(w, 0.1).auto_s);
    for (int s = 0; s < 2000; ++s) sim.step();
    const auto p = w.contacts.find(BodyRef(BodyKind::grain, 0), wall_ref(0));
    ASSERT_TRUE(p.has_value());
    ASSERT_GT(w.contacts.tangential[*p].spring_m.norm(), 0.0);

    w.point_loads.clear();
    Vec3 off = w.bodies[0].x[0][0];
    off.z() = r + 0.1 * effective_skin_m(w);
    place_body(w, BodyRef(BodyKind::grain, 0), off);
    begin_run(w, sim.pool());
    ASSERT_TRUE(w.contacts.find(BodyRef(BodyKind::grain, 0), wall_ref(0)).has_value()) << "still a candidate";
    EXPECT_FALSE(w.contacts.touching[*p]);
    EXPECT_TRUE(same_bits(w.contacts.tangential[*p], TangentialState{}));
    EXPECT_EQ(w.contacts.output[*p].force_n, Vec3::Zero());
    EXPECT_EQ(w.body_force_n[0][0], Vec3::Zero()) << "no gravity, no load, no contact force";
}
