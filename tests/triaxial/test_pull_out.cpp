// Pulling the wire out (engine/triaxial/pull_out.hpp, the free-standing
// test's pull_out phase) against physics: a straight wire lying on a
// frictional plate slides at the Coulomb force of its weight, the drive's
// force on the pulled node and the end segment's tension are the same pull
// measured two ways, a wire buried under grains takes more than the same wire
// with nothing on it, and the test is bit-identical on 1 and 2 threads.
#include "forces/wire_forces.hpp"
#include "scene.hpp"
#include "simulation.hpp"
#include "specimen/preparation.hpp"
#include "state/state_hash.hpp"
#include "timestep.hpp"
#include "triaxial/free_standing.hpp"
#include "triaxial/pull_out.hpp"

#include "column_specimens.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <optional>
#include <utility>

using namespace wiredem::engine;

namespace {

/// A straight wire of `nodes` paper-wire nodes along +x lying on a plate at
/// z = 0 under g = 10 m/s², settled for 5 ms (the auto δt).
void wire_on_plate(Simulation& sim, int nodes)
{
    World& w = sim.world;
    w = World{};
    w.gravity_m_per_s2 = Vec3(0.0, 0.0, -10.0);
    const std::uint8_t plate_mat = add_material(w, Material{1e9, 0.3, 7800.0});
    add_wall(w, make_plate(0.0, +1.0, plate_mat));
    const WireSpec spec{};
    configure_wire(w, spec);
    for (int i = 0; i < nodes; ++i) append_wire_node(w, Vec3(i * spec.segment_length_m, 0.0, spec.radius_m));
    w.dt_s = stable_time_step(w).auto_s;
    for (double t = 0.0; t < 5e-3; t += w.dt_s) sim.step();
}

/// Mean pull force and end tension (along the pull) over the steps of
/// [t_from, t_to) of a pull started now [N].
struct MeanPull {
    double force_n = 0.0;
    double tension_along_n = 0.0;
    double drive_up_n = 0.0;   ///< the drive's vertical force on the pulled node
};
MeanPull pull_for(Simulation& sim, const PullOutSettings& p, double t_from_s, double t_to_s)
{
    World& w = sim.world;
    MeanPull m;
    int n = 0;
    double dbg_fn = 0, dbg_fx = 0, dbg_vy = 0, dbg_vz = 0;
    for (double t = 0.0; t < t_to_s; t += w.dt_s) {
        if (t <= p.ramp_time_s + w.dt_s) drive_pulled_node(w, p, t + w.dt_s);
        sim.step();
        if (t < t_from_s) continue;
        const PullForces f = pull_forces(w, p.end, p.direction.normalized());
        m.force_n += f.pull_force_n;
        m.tension_along_n += f.end_tension_along_n;
        m.drive_up_n -= w.force_of(BodyKind::wire)[pulled_node(w, p.end)].z();
        for (std::size_t c = 0; c < w.contacts.pair_count(); ++c) if (w.contacts.touching[c]) { dbg_fn += w.contacts.output[c].normal_force_n; dbg_fx += w.contacts.output[c].force_n.x(); }
        for (std::size_t c = w.contacts.pair_count(); c < w.contacts.output.size(); ++c) { dbg_fn += w.contacts.output[c].normal_force_n; dbg_fx += w.contacts.output[c].force_n.x(); }
        for (std::size_t i = 0; i < w.of(BodyKind::wire).size(); ++i) { dbg_vy += std::abs(w.of(BodyKind::wire).x[1][i].y()/w.dt_s); dbg_vz += std::abs(w.of(BodyKind::wire).x[1][i].z()/w.dt_s);}
        ++n;
    }
    m.force_n /= n;
    m.tension_along_n /= n;
    m.drive_up_n /= n;
    std::printf("dbg fn %g fx %g vy %g vz %g\n", dbg_fn/n, dbg_fx/n, dbg_vy/n, dbg_vz/n);
    return m;
}

constexpr double ring_wire_mass_scale = 1e3;

/// A column of soft grains (r = 1 mm) in simple-cubic layers inside a rigid
/// membrane of radius 6 mm: two layers, an open wire ring (radius 3.6 mm,
/// 300°) lying on them, then `layers_above` layers on the ring; the top
/// plate on the highest grain or node. The wire's masses are scaled by 10³
/// (a free-standing test with real_weights {1, 10³} gives it its real
/// weight), so that it does not set δt. Returns the top plate's wall.
std::size_t ring_column(Simulation& sim, int layers_above)
{
    World& w = sim.world;
    w = World{};
    w.contact.normal_damping_s = 2e-5;
    w.contact.tangential.friction_coeff = 0.5;
    const double r = 1e-3;
    const std::uint8_t grain_mat = add_material(w, Material{1e8, 0.3, 2600.0});
    const std::uint8_t plate_mat = add_material(w, Material{1e9, 0.3, 7800.0});
    add_wall(w, make_plate(0.0, +1.0, plate_mat));
    WireSpec wire;
    wire.density_scale = ring_wire_mass_scale;
    configure_wire(w, wire);
    const double gap_m = 2.0 * wire.radius_m + 0.2e-3, a = 2.0 * r;
    double z = r, wire_z = 0.0, top_m = 0.0;
    for (int layer = 0; layer < 2 + layers_above; ++layer) {
        for (int i = -2; i <= 2; ++i)
            for (int j = -2; j <= 2; ++j)
                if (std::hypot(i * a, j * a) < 4.5e-3) add_grain(w, Vec3(i * a, j * a, z), r, grain_mat);
        top_m = z + r;
        if (layer == 1) {
            wire_z = z + r + 0.5 * gap_m;
            top_m = wire_z + wire.radius_m;
            z += gap_m;
        }
        z += a;
    }
    const double ring_m = 3.6e-3;
    const auto nodes = static_cast<int>((300.0 / 360.0) * 2.0 * std::numbers::pi * ring_m / wire.segment_length_m);
    for (int n = 0; n < nodes; ++n) {
        const double phi = n * wire.segment_length_m / ring_m;
        append_wire_node(w, Vec3(ring_m * std::cos(phi), ring_m * std::sin(phi), wire_z));
    }
    MembraneSpec membrane = test::test_membrane(6e-3, top_m + 1e-3);
    build_membrane(w, membrane);
    set_membrane_rigid(w, true);
    const std::size_t top = add_wall(w, make_plate(top_m, -1.0, plate_mat));
    w.dt_s = stable_time_step(w).auto_s;
    return top;
}

/// The free-standing test's settings for the ring column: a quick removal
/// and settling, then the last node pulled up at 0.1 m/s by `length_m`.
FreeStandingSettings pull_settings(double length_m)
{
    FreeStandingSettings s;
    s.removal_time_s = 5e-3;
    s.removal_distance_m = 1e-3;
    s.escape_distance_m = 0.02;
    s.max_settling_time_s = 0.02;
    s.sample_interval_s = 0.2e-3;
    s.real_weights = TriaxialSettings::MassScaling{1.0, ring_wire_mass_scale};
    PullOutSettings p;
    p.speed_m_per_s = 0.1;
    p.length_m = length_m;
    p.max_time_s = 0.2;
    s.pull_out = p;
    return s;
}

} // namespace

// A straight wire lying on a plate, pulled along its length at v above the
// shear damping's crossover μ/γ_t (0.3 mm/s): every node but the driven one
// slides with the Coulomb force μ F_n. The driven node is kinematic and
// touches no wall (a kinematic body has no wall contacts): the drive holds
// up the wire's end with a vertical force F_z, and at rest vertically the
// plate carries the rest, Σ F_n = N m g − F_z. So the pull, once the whole
// wire slides and the start's axial waves have died out (the slowest mode,
// ~0.1 ms, is damped within ~2 ms by the wire's dashpots), is
// μ (N m g − F_z) (measured F_z = 0.95 m g: the drive holds about its own
// node's weight; its neighbours lie on the plate). The end segment carries the same force: the
// drive's force along x and the segment's tension differ only by the end
// joint's bending force, zero for a straight wire.
TEST(PullOut, AWireLyingOnAPlateSlidesAtTheCoulombForceOfItsWeight)
{
    Simulation sim(1);
    const int nodes = 21;
    wire_on_plate(sim, nodes);
    const World& w = sim.world;
    PullOutSettings p;
    p.direction = Vec3(1.0, 0.0, 0.0);
    p.speed_m_per_s = 0.1;
    p.ramp_time_s = 1e-3;
    const MeanPull m = pull_for(sim, p, 5e-3, 10e-3);
    const double mu = w.contact.tangential.friction_coeff;
    const double node_weight_n = w.wire.node_mass_kg * 10.0;
    std::printf("the drive holds %.3f node weights\n", m.drive_up_n / node_weight_n);
    EXPECT_GT(m.drive_up_n, 0.0);
    EXPECT_LT(m.drive_up_n, 3.0 * node_weight_n);
    const double expected_n = mu * (nodes * node_weight_n - m.drive_up_n);
    EXPECT_NEAR(m.force_n, expected_n, 0.01 * expected_n);
    EXPECT_NEAR(m.tension_along_n, m.force_n, 1e-6 * expected_n);
    // Pulled from its other end (towards −x), the same.
    Simulation sim2(1);
    wire_on_plate(sim2, nodes);
    p.end = WireEnd::first;
    p.direction = Vec3(-1.0, 0.0, 0.0);
    const MeanPull m2 = pull_for(sim2, p, 5e-3, 10e-3);
    EXPECT_NEAR(m2.force_n, mu * (nodes * node_weight_n - m2.drive_up_n), 0.01 * expected_n);
}

// Lifted straight up off the plate, the end node hangs in the air: the
// drive holds its segment, its joint and its own weight,
// F = T (û · d̂) + m g − F_joint,z: the pull measured two ways, from the
// force the step gathered on the node and from the end segment's tension.
TEST(PullOut, ThePullIsTheEndSegmentsTensionPlusWhatActsOnTheDrivenNode)
{
    Simulation sim(1);
    wire_on_plate(sim, 21);
    World& w = sim.world;
    PullOutSettings p; // the last node, straight up
    p.speed_m_per_s = 0.02;
    p.ramp_time_s = 1e-3;
    const std::uint32_t node = pulled_node(w, p.end);
    for (double t = 0.0; t < 5e-3; t += w.dt_s) {
        drive_pulled_node(w, p, t + w.dt_s);
        sim.step();
    }
    const PullForces f = pull_forces(w, p.end, Vec3(0.0, 0.0, 1.0));
    const double weight_n = w.wire.node_mass_kg * 10.0;
    const double joint_n = w.wire_forces.bending_force_n[2][node - 1].z();
    EXPECT_NEAR(f.pull_force_n, f.end_tension_along_n + weight_n - joint_n, 1e-9 * f.pull_force_n);
}

// A wire held in its surroundings takes more to pull than the same wire
// lying free: the load on it presses it from above and onto the plate, and
// friction acts on both of its faces. The surroundings here are a second
// rigid plate pressed 1 µm into the top of the wire (a confining load P on
// it; the grains of a column do the same with a bumpier surface, which
// adds interlocking on top of the friction): the sliding wire needs μ times
// every normal force on it, μ (Σ F_n,bottom + Σ F_n,top) = μ (N m g − F_z + 2 P),
// read from the contacts and compared with the pull. At 0.5 m/s: slower,
// the contacts' stick–slip (a sliding contact sticks again when its slip
// turns back within a step, docs/model.md) takes the mean friction below
// μ F_n, the more so the slower and the harder pressed (measured on the
// free wire: 0.83 μ at 5 mm/s, 0.91 μ at 2 cm/s, 0.996 μ at 0.1 m/s;
// pressed, 0.956 μ at 0.1 m/s, 0.999 μ at 0.5 m/s).
TEST(PullOut, AWirePressedByItsSurroundingsTakesMuTimesEveryNormalForceOnIt)
{
    Simulation sim(1);
    const int nodes = 21;
    wire_on_plate(sim, nodes);
    World& w = sim.world;
    const double mu = w.contact.tangential.friction_coeff;
    const double node_weight_n = w.wire.node_mass_kg * 10.0;
    PullOutSettings p;
    p.direction = Vec3(1.0, 0.0, 0.0);
    p.speed_m_per_s = 0.5;
    p.ramp_time_s = 1e-3;
    const MeanPull free = pull_for(sim, p, 5e-3, 10e-3);

    Simulation pressed_sim(1);
    wire_on_plate(pressed_sim, nodes);
    World& b = pressed_sim.world;
    double top_m = 0.0;
    for (const Vec3& x : b.of(BodyKind::wire).x[0]) top_m = std::max(top_m, x.z() + b.wire.radius_m);
    add_wall(b, make_plate(top_m - 1e-6, -1.0, b.walls[0].material));
    for (double t = 0.0; t < 2e-3; t += b.dt_s) pressed_sim.step();
    // Every normal force on the wire's nodes but the driven one's (a
    // kinematic node touches no wall), averaged over the same steps as the pull.
    double pull_n = 0.0, normal_sum_n = 0.0;
    int n = 0;
    for (double t = 0.0; t < 10e-3; t += b.dt_s) {
        if (t <= p.ramp_time_s + b.dt_s) drive_pulled_node(b, p, t + b.dt_s);
        pressed_sim.step();
        if (t < 5e-3) continue;
        pull_n += pull_forces(b, p.end, p.direction).pull_force_n;
        const ContactList& c = b.contacts;
        for (std::size_t i = 0; i < c.size(); ++i)
            if (c.touching[i] && c.first[i].kind() == BodyKind::wire) normal_sum_n += c.output[i].normal_force_n;
        ++n;
    }
    pull_n /= n;
    normal_sum_n /= n;
    std::printf("pull: free %.4g N, pressed %.4g N (normal forces %.4g N, the wire's weight %.4g N)\n", free.force_n,
        pull_n, normal_sum_n, nodes * node_weight_n);
    EXPECT_GT(normal_sum_n, 10.0 * nodes * node_weight_n) << "the load must be far more than the wire's weight";
    EXPECT_NEAR(pull_n, mu * normal_sum_n, 0.01 * mu * normal_sum_n);
    EXPECT_GT(pull_n, 10.0 * free.force_n);
}

// The same pull-out on 1 and 2 threads: the same bits; and continued from
// the World and the driver's state saved in the middle of the pull (what a
// checkpoint holds), the same end. The run itself: a column of grains
// whose formwork is removed, settled, and the top end of its wire pulled up
// by 2 mm, which ends it; its rows are the phase's.
TEST(PullOut, IsBitIdenticalOnOneAndTwoThreadsAndContinuedMidPull)
{
    std::optional<std::pair<World, FreeStandingDriverState>> saved;
    auto run = [&](unsigned threads, FreeStandingResult& out) {
        Simulation sim(threads);
        const std::size_t top = ring_column(sim, 2);
        FreeStandingContinuation c;
        c.between_steps = [&](const World& w, const FreeStandingDriverState& st) {
            if (threads == 2 && !saved && st.phase == FreeStandingPhase::pull_out && st.steps > st.phase_start_step + 2000)
                saved.emplace(w, st);
        };
        auto r = run_free_standing(sim, top, pull_settings(2e-3), {}, c);
        EXPECT_TRUE(r.ok()) << r.error();
        if (r.ok()) out = std::move(r.value());
        return state_hash(sim.world);
    };
    FreeStandingResult one, two;
    const auto h1 = run(1, one), h2 = run(2, two);
    EXPECT_EQ(h1, h2);
    ASSERT_TRUE(one.pull_out && two.pull_out);
    const PullOutReading& p = *one.pull_out;
    EXPECT_EQ(p.end, PullOutEnd::length);
    EXPECT_GE(p.pulled_length_m, 2e-3);
    EXPECT_GT(p.peak_pull_force_n, 0.0);
    EXPECT_FALSE(one.compression.has_value());
    EXPECT_EQ(p.series.size(), one.series.size() - one.loading_start_sample);
    EXPECT_EQ(one.series.phase[one.loading_start_sample], static_cast<std::uint8_t>(FreeStandingPhase::pull_out));
    EXPECT_GT(p.wire_in_column_before_m, 0.0);
    const PullOutSeries &a = p.series, &b = two.pull_out->series;
    ASSERT_EQ(a.size(), b.size());
    ASSERT_GT(a.size(), 0u);
    EXPECT_EQ(0, std::memcmp(a.pull_force_n.data(), b.pull_force_n.data(), a.size() * sizeof(double)));
    EXPECT_EQ(0, std::memcmp(&p.peak_pull_force_n, &two.pull_out->peak_pull_force_n, sizeof(double)));

    ASSERT_TRUE(saved.has_value());
    Simulation rest(1);
    rest.world = saved->first;
    FreeStandingContinuation from;
    from.from = saved->second;
    const std::size_t top = rest.world.walls.size() - 1;
    const auto r = run_free_standing(rest, top, pull_settings(2e-3), {}, from);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(state_hash(rest.world), h2);
    ASSERT_TRUE(r.value().pull_out);
    EXPECT_EQ(0, std::memcmp(r.value().pull_out->series.pull_force_n.data(), b.pull_force_n.data(), b.size() * sizeof(double)));
    EXPECT_EQ(r.value().pull_out->peak_pull_force_n, two.pull_out->peak_pull_force_n);
}

// A breakable wire pulled harder than its strength breaks during the pull:
// the reading says so, the break is the test's, after the pull began, and
// the piece left behind stays in the column. The ring column's wire
// (ε_b = 10⁻²: F_b = E_w π r_w² ε_b = 7.9 N; a smaller ε_b breaks the ring,
// laid straight-jointed, as it settles) is jerked to 3 m/s within 1 ms:
// accelerating its scaled mass takes up to ramp_inertia_n = 69 N, far past
// F_b (the row means, over 0.2 ms, peak at 1.6 N). Measured: one break;
// the wire in the column falls by that segment only (17.5 → 16.25 mm).
TEST(PullOut, ABreakableWirePulledPastItsStrengthBreaksAndThePieceLeftStaysIn)
{
    Simulation sim(1);
    const std::size_t top = ring_column(sim, 2);
    sim.world.wire.breaking_strain = 1e-2;
    FreeStandingSettings s = pull_settings(2e-3);
    s.pull_out->ramp_time_s = 1e-3;
    s.pull_out->speed_m_per_s = 3.0;
    const auto r = run_free_standing(sim, top, s);
    ASSERT_TRUE(r.ok()) << r.error();
    ASSERT_TRUE(r.value().pull_out);
    const PullOutReading& p = *r.value().pull_out;
    std::printf("breaks %zu, peak %.4g N, ramp inertia %.4g N, wire in column %.4g -> %.4g m\n",
        r.value().wire_breaks.size(), p.peak_pull_force_n, p.ramp_inertia_n, p.wire_in_column_before_m, p.wire_in_column_m);
    EXPECT_TRUE(p.wire_broke);
    ASSERT_FALSE(r.value().wire_breaks.empty());
    const double pull_began_s = r.value().series.time_s[r.value().loading_start_sample] - s.sample_interval_s;
    EXPECT_GT(r.value().wire_breaks.back().test_time_s, pull_began_s);
    EXPECT_GT(p.wire_in_column_m, 0.0);
}

// Settings out of range name their field; a pull-out with a dead load is refused.
TEST(PullOut, RejectsSettingsOutOfRangeNamingTheField)
{
    FreeStandingSettings s = pull_settings(1e-3);
    s.pull_out->speed_m_per_s = 0.0;
    auto e = free_standing_settings_error(s);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->field, "pull_out.speed_m_per_s");
    s = pull_settings(1e-3);
    s.pull_out->direction = Vec3::Zero();
    e = free_standing_settings_error(s);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->field, "pull_out.direction");
    s = pull_settings(1e-3);
    s.pull_out->max_time_s = -1.0;
    EXPECT_EQ(free_standing_settings_error(s)->field, "pull_out.max_time_s");
    s = pull_settings(1e-3);
    s.dead_load = DeadLoad{1.0};
    EXPECT_EQ(free_standing_settings_error(s)->field, "pull_out");
}
