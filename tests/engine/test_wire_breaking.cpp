// A wire that breaks, and a wire that is cut (issue 39): a segment stretched
// past the breaking strain ε_b breaks at the load E_w A ε_b, its two ends carry
// nothing after it, the energy its spring held is what the break takes out,
// the events are the same for any thread count and survive a snapshot; cuts
// at positions and after every k loops; the pieces the wire falls into.
#include "energy.hpp"
#include "forces/wire_forces.hpp"
#include "io/snapshot.hpp"
#include "simulation.hpp"
#include "specimen/wire_cuts.hpp"
#include "state/state_hash.hpp"
#include "timestep.hpp"
#include "triaxial/sampling.hpp"
#include "wired_column.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <unistd.h>

using namespace wiredem::engine;

namespace {

const WireSpec paper_wire{}; // r_w = 0.5 mm, l_w = 1.25 mm, E_w = 1 GPa, ρ_w = 1000

double area_m2() { return std::numbers::pi * paper_wire.radius_m * paper_wire.radius_m; }

/// A straight wire of `nodes` nodes along +x, each segment at strain
/// `strain`, no gravity, breaking strain ε_b, the auto δt.
void straight_wire(World& w, int nodes, double strain, double breaking_strain)
{
    w = World{};
    w.gravity_m_per_s2 = Vec3::Zero();
    WireSpec spec = paper_wire;
    spec.breaking_strain = breaking_strain;
    configure_wire(w, spec);
    for (int i = 0; i < nodes; ++i) append_wire_node(w, Vec3(i * (1.0 + strain) * spec.segment_length_m, 0, 0));
    w.dt_s = stable_time_step(w).auto_s;
}

double total_energy_j(Simulation& sim)
{
    return kinetic_energy_j(sim.world, sim.pool()) + elastic_energy(sim.world, sim.pool()).total_j();
}

std::filesystem::path temp_path(const std::string& name)
{
    return std::filesystem::temp_directory_path() / ("wiredem_test_wire_breaking_" + std::to_string(::getpid()) + "_" + name);
}

/// The wired column (tests/engine/wired_column.hpp) with a breakable ring:
/// ε_b = 2·10⁻⁴ breaks a few of its segments within the first few hundred steps.
constexpr double column_breaking_strain = 2e-4;
std::size_t build_breakable_column(World& w)
{
    const std::size_t top = test::build_wired_column(w, Integrator::gear5);
    w.wire.breaking_strain = column_breaking_strain;
    return top;
}

} // namespace

TEST(WireBreaking, APulledWireBreaksAtTheAnalyticalLoad)
{
    // Node 0 held, the last node pulled by a force ramped up over T = 5 ms,
    // ~300 periods of the bar's slowest axial mode (ω = (π/2L)√(E/ρ) ≈ 6·10⁴
    // rad/s): the bar follows the load quasi-statically, the dynamic part of
    // its strain ~1/(ωT) ≈ 0.3 % of the static one, and the load grows by
    // 2·10⁻⁵ of F_b per step. So it breaks at F_b = E_w A ε_b within 1 %.
    Simulation sim(1);
    World& w = sim.world;
    const int nodes = 21;
    const double eps_b = 0.01;
    straight_wire(w, nodes, 0.0, eps_b);
    set_motion(w, {BodyKind::wire, 0}, Motion::fixed);
    const double f_b = paper_wire.youngs_modulus_pa * area_m2() * eps_b;
    const double ramp_s = 5e-3;
    w.point_loads.set(BodyRef(BodyKind::wire, nodes - 1), Vec3::Zero());
    double load_at_break = 0.0;
    for (std::uint64_t n = 0; n < static_cast<std::uint64_t>(2.0 * ramp_s / w.dt_s) && w.wire_breaks.empty(); ++n) {
        const double load = f_b * w.time_s / ramp_s;
        w.point_loads.set(BodyRef(BodyKind::wire, nodes - 1), Vec3(load, 0, 0));
        sim.step();
        load_at_break = load;
    }
    // Its strain is uniform but for the dynamic part: the segments that
    // cross ε_b in the same step all break in it (before the release of the
    // first can reach them).
    ASSERT_GE(w.wire_breaks.size(), 1u);
    for (const WireBreak& e : w.wire_breaks) EXPECT_EQ(e.time_s, w.wire_breaks[0].time_s) << "all in the first step";
    std::printf("broke at %.6f F_b, %zu segments:", load_at_break / f_b, w.wire_breaks.size());
    for (const WireBreak& e : w.wire_breaks) std::printf(" %u (strain %.6g)", e.segment, e.strain);
    std::printf("\n");
    const WireBreak b = w.wire_breaks[0];
    EXPECT_NEAR(load_at_break / f_b, 1.0, 0.01);
    EXPECT_EQ(b.cause, WireBreakCause::strain);
    EXPECT_GT(b.strain, eps_b);
    EXPECT_NEAR(b.time_s, w.time_s, 1e-3 * w.dt_s) << "recorded at the end of the step it broke in";
    const double dl = b.strain * paper_wire.segment_length_m;
    EXPECT_DOUBLE_EQ(b.released_energy_j, 0.5 * w.wire.axial_stiffness_n_per_m * dl * dl);

    // The broken wire's ends carry no tension: with the load taken off, the
    // removed segment exerts nothing at any step, its end joints bend no
    // more, and every piece, its ends free, rings down to no strain at all
    // (the wire's damping: the slowest mode has ξ ≈ 0.3 ω/ω_max ≈ 0.01, so
    // 20 ms are ~12 decay times).
    w.point_loads.clear();
    const std::uint32_t s = b.segment;
    for (int block = 0; block < 20; ++block) {
        ASSERT_EQ(sim.run(static_cast<std::uint64_t>(1e-3 / w.dt_s)).end, RunEnd::completed);
        EXPECT_EQ(w.wire_forces.segment_force_n[s], Vec3::Zero());
        EXPECT_EQ(w.wire_forces.segment_strain[s], 0.0);
    }
    double strain_left = 0.0;
    for (double e : w.wire_forces.segment_strain) strain_left = std::max(strain_left, std::abs(e));
    EXPECT_LT(strain_left, 1e-3 * eps_b) << "every piece, free at its broken ends, relaxes";
    for (const WireBreak& e : w.wire_breaks) EXPECT_GT(e.strain, eps_b);
    // The end joints bend no more: node s ends one piece, s + 1 starts the next.
    for (std::uint32_t j : {s, s + 1})
        if (j >= 1 && j + 1 < static_cast<std::uint32_t>(nodes)) {
            for (const auto& on : w.wire_forces.bending_force_n) EXPECT_EQ(on[j], Vec3::Zero()) << "joint " << j;
            EXPECT_EQ(w.wire_rest_angle_rad[j], 0.0);
        }
}

TEST(WireBreaking, ACutTakesOutTheEnergyItsSpringHeldAndNoMore)
{
    // A wire held at both ends, stretched by 0.5 % and at rest: cutting its
    // middle segment removes exactly ½ k (ε l_w)² of elastic energy; from then
    // on the energy only falls (the wire's damping) and the two pieces, each
    // held at one end, relax to no strain.
    Simulation sim(2);
    World& w = sim.world;
    const int nodes = 31;
    const double strain = 5e-3;
    straight_wire(w, nodes, strain, std::numeric_limits<double>::infinity());
    set_motion(w, {BodyKind::wire, 0}, Motion::fixed);
    set_motion(w, {BodyKind::wire, static_cast<std::uint32_t>(nodes - 1)}, Motion::fixed);
    const double e0 = total_energy_j(sim);
    const double k = w.wire.axial_stiffness_n_per_m, dl = strain * paper_wire.segment_length_m;
    EXPECT_NEAR(e0, (nodes - 1) * 0.5 * k * dl * dl, 1e-9 * e0);

    ASSERT_TRUE(cut_wire_segment(w, 15));
    EXPECT_FALSE(cut_wire_segment(w, 15)) << "a segment is cut once";
    EXPECT_FALSE(cut_wire_segment(w, nodes - 1)) << "there is no such segment";
    ASSERT_EQ(w.wire_breaks.size(), 1u);
    const WireBreak& cut = w.wire_breaks[0];
    EXPECT_EQ(cut.cause, WireBreakCause::cut);
    EXPECT_NEAR(cut.strain, strain, 1e-12);
    EXPECT_NEAR(cut.released_energy_j, 0.5 * k * dl * dl, 1e-9 * cut.released_energy_j);
    const double e_after = e0 - cut.released_energy_j;
    EXPECT_NEAR(total_energy_j(sim), e_after, 1e-12 * e0) << "the cut takes out its spring's energy, nothing else";

    double previous = e_after;
    for (int block = 0; block < 100; ++block) {
        ASSERT_EQ(sim.run(2000).end, RunEnd::completed);
        const double e = total_energy_j(sim);
        EXPECT_LE(e, previous * (1.0 + 1e-9)) << "after " << (block + 1) * 2000 << " steps";
        previous = e;
    }
    EXPECT_LT(previous, 1e-2 * e_after);
    const std::vector<WirePiece> pieces = wire_pieces(w);
    ASSERT_EQ(pieces.size(), 2u);
    EXPECT_EQ(pieces[0].first_node, 0u);
    EXPECT_EQ(pieces[0].nodes, 16u);
    EXPECT_EQ(pieces[1].first_node, 16u);
    EXPECT_EQ(pieces[1].nodes, 15u);
    EXPECT_DOUBLE_EQ(pieces[0].rest_length_m, 15 * paper_wire.segment_length_m);
    EXPECT_NEAR(pieces[0].length_m, pieces[0].rest_length_m, 1e-3 * pieces[0].rest_length_m) << "relaxed";
}

TEST(WireBreaking, ABreakInAStepTakesOutTheEnergyOfItsSpring)
{
    // A wire at rest, held at both ends, its segments at 0.5 % strain but one
    // at 0.8 %, with ε_b = 0.7 % (above the 0.5 % pieces with room for the
    // ringing of a discrete chain released at one end, which can overshoot
    // by about a quarter): that segment breaks in the first step, and
    // the energy right after it is the energy before less ½ k (ε l_w)² of the
    // broken spring, to the integrator's error over one step.
    Simulation sim(1);
    World& w = sim.world;
    const int nodes = 21;
    straight_wire(w, nodes, 5e-3, 7e-3);
    auto& x = w.of(BodyKind::wire).x[0];
    for (int i = 11; i < nodes; ++i) x[i].x() += 3e-3 * paper_wire.segment_length_m; // segment 10 at 0.8 %
    set_motion(w, {BodyKind::wire, 0}, Motion::fixed);
    set_motion(w, {BodyKind::wire, static_cast<std::uint32_t>(nodes - 1)}, Motion::fixed);
    const double e0 = total_energy_j(sim);
    sim.step();
    ASSERT_EQ(w.wire_breaks.size(), 1u);
    EXPECT_EQ(w.wire_breaks[0].segment, 10u);
    const double released = w.wire_breaks[0].released_energy_j;
    EXPECT_GT(released, 0.1 * e0);
    EXPECT_NEAR(total_energy_j(sim), e0 - released, 1e-3 * released);
    double previous = e0 - released;
    for (int block = 0; block < 50; ++block) {
        ASSERT_EQ(sim.run(2000).end, RunEnd::completed);
        const double e = total_energy_j(sim);
        EXPECT_LE(e, previous * (1.0 + 1e-9) + 1e-6 * released);
        previous = e;
    }
    EXPECT_EQ(w.wire_breaks.size(), 1u) << "the other segments, at 0.5 %, relax and hold";
}

TEST(WireBreaking, AFiniteBreakingStrainNeverReachedStepsLikeAnUnbreakableWire)
{
    // The check for breaks changes nothing while no segment breaks: the wired
    // column with ε_b = 10³ hashes like the unbreakable one at every block.
    Simulation a(2), b(2);
    test::build_wired_column(a.world, Integrator::gear5);
    test::build_wired_column(b.world, Integrator::gear5);
    b.world.wire.breaking_strain = 1e3;
    for (int block = 0; block < 6; ++block) {
        ASSERT_EQ(a.run(100).end, RunEnd::completed);
        ASSERT_EQ(b.run(100).end, RunEnd::completed);
        ASSERT_EQ(state_hash(a.world), state_hash(b.world)) << "block " << block;
    }
    EXPECT_TRUE(b.world.wire_breaks.empty());
}

TEST(WireBreaking, BreaksAreTheSameForOneToFourThreads)
{
    std::vector<WireBreak> reference;
    std::vector<std::uint64_t> reference_hashes;
    for (unsigned threads : {1u, 2u, 3u, 4u}) {
        Simulation sim(threads);
        build_breakable_column(sim.world);
        std::vector<std::uint64_t> hashes;
        for (int block = 0; block < 6; ++block) {
            ASSERT_EQ(sim.run(100).end, RunEnd::completed);
            hashes.push_back(state_hash(sim.world));
        }
        if (threads == 1) {
            reference = sim.world.wire_breaks;
            reference_hashes = hashes;
            ASSERT_FALSE(reference.empty()) << "the column's ring breaks at ε_b = " << column_breaking_strain;
        } else {
            EXPECT_EQ(sim.world.wire_breaks, reference) << threads << " threads";
            EXPECT_EQ(hashes, reference_hashes) << threads << " threads";
        }
    }
}

TEST(WireBreaking, ABrokenWireRestoresFromASnapshotAndContinuesBitIdentically)
{
    Simulation original(2);
    build_breakable_column(original.world);
    ASSERT_EQ(original.run(300).end, RunEnd::completed);
    ASSERT_FALSE(original.world.wire_breaks.empty()) << "broken before the snapshot";
    const std::size_t breaks_at_save = original.world.wire_breaks.size();
    const std::filesystem::path path = temp_path("snapshot.h5");
    const auto saved = save_snapshot(original.world, path);
    ASSERT_TRUE(saved.ok()) << saved.error();
    auto restored = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_TRUE(restored.ok()) << restored.error();
    Simulation resumed(3);
    resumed.world = std::move(restored).value();
    EXPECT_EQ(resumed.world.wire_breaks, original.world.wire_breaks);
    EXPECT_EQ(resumed.world.wire.breaking_strain, column_breaking_strain);
    for (int block = 0; block < 4; ++block) {
        ASSERT_EQ(original.run(100).end, RunEnd::completed);
        ASSERT_EQ(resumed.run(100).end, RunEnd::completed);
        ASSERT_EQ(state_hash(resumed.world), state_hash(original.world)) << "block " << block;
    }
    EXPECT_EQ(resumed.world.wire_breaks, original.world.wire_breaks);
    EXPECT_GE(original.world.wire_breaks.size(), breaks_at_save);
}

TEST(WireBreaking, AWholeWiresHashAndSnapshotDoNotListBreaks)
{
    World w;
    test::build_wired_column(w, Integrator::gear5);
    const std::uint64_t whole = state_hash(w);
    w.wire.breaking_strain = 0.5; // a model parameter: not in the state hash
    EXPECT_EQ(state_hash(w), whole);
    ASSERT_TRUE(cut_wire_segment(w, 3));
    EXPECT_NE(state_hash(w), whole) << "a removed segment is state";
}

TEST(WireCuts, APositionCutsTheSegmentThatHoldsItAndOnePastTheWireIsAnError)
{
    World w;
    straight_wire(w, 11, 0.0, std::numeric_limits<double>::infinity()); // 10 segments, 12.5 mm
    const double l0 = paper_wire.segment_length_m;
    auto segments = wire_cut_segments(w, WireCuts{.at_m = {0.0, 2.5 * l0, 3.0 * l0, 9.99 * l0}});
    ASSERT_TRUE(segments.ok()) << segments.error();
    EXPECT_EQ(segments.value(), (std::vector<std::uint32_t>{0, 2, 3, 9}));
    const auto past = cut_wire(w, WireCuts{.at_m = {l0, 10.0 * l0}});
    ASSERT_FALSE(past.ok());
    EXPECT_NE(past.error().find("[1]"), std::string::npos) << past.error();
    EXPECT_NE(past.error().find("0.0125"), std::string::npos) << past.error();
    EXPECT_TRUE(w.wire_breaks.empty()) << "nothing cut on an error";

    const auto made = cut_wire(w, WireCuts{.at_m = {2.5 * l0, 7.2 * l0}});
    ASSERT_TRUE(made.ok());
    EXPECT_EQ(made.value(), 2u);
    const std::vector<WirePiece> pieces = wire_pieces(w);
    ASSERT_EQ(pieces.size(), 3u);
    EXPECT_EQ(pieces[0].nodes, 3u); // nodes 0–2
    EXPECT_EQ(pieces[1].nodes, 5u); // nodes 3–7
    EXPECT_EQ(pieces[2].nodes, 3u); // nodes 8–10
    double rest = 0.0;
    for (const WirePiece& p : pieces) rest += p.rest_length_m;
    EXPECT_NEAR(rest, (10 - 2) * l0, 1e-15) << "the pieces are the wire less its removed segments";
}

TEST(WireCuts, EveryKLoopsCutsAHelixOncePerKTurns)
{
    // A helix of radius 6 mm, 3.5 turns, pitch 2 mm, laid at l_w along its
    // arc (about 30 segments per turn), centred on the axis: every loop cuts
    // it 3 times, at the ends of its turns, into pieces one turn long; every
    // second loop once.
    World w;
    w.gravity_m_per_s2 = Vec3::Zero();
    configure_wire(w, paper_wire);
    const double radius = 6e-3, pitch = 2e-3, l0 = paper_wire.segment_length_m;
    const double turn_m = std::hypot(2.0 * std::numbers::pi * radius, pitch);
    const int nodes = static_cast<int>(3.5 * turn_m / l0);
    for (int i = 0; i < nodes; ++i) {
        const double theta = 2.0 * std::numbers::pi * i * l0 / turn_m;
        append_wire_node(w, Vec3(radius * std::cos(theta), radius * std::sin(theta), pitch * theta / (2.0 * std::numbers::pi)));
    }
    const auto every_two = wire_cut_segments(w, WireCuts{.at_m = {}, .every_loops = 2});
    ASSERT_TRUE(every_two.ok());
    EXPECT_EQ(every_two.value().size(), 1u);
    ASSERT_TRUE(cut_wire(w, WireCuts{.at_m = {}, .every_loops = 1}).ok());
    ASSERT_EQ(w.wire_breaks.size(), 3u);
    const std::vector<WirePiece> pieces = wire_pieces(w);
    ASSERT_EQ(pieces.size(), 4u);
    for (int p = 1; p <= 2; ++p) EXPECT_NEAR(pieces[p].rest_length_m, turn_m, 1.5 * l0) << "piece " << p << " is one turn";
    // Clockwise the same: the winding's size counts.
    World mirrored = w;
    mirrored.wire_breaks.clear();
    for (Vec3& x : mirrored.of(BodyKind::wire).x[0]) x.y() = -x.y();
    EXPECT_EQ(wire_cut_segments(mirrored, WireCuts{.at_m = {}, .every_loops = 1}).value().size(), 3u);
}

TEST(PeakFailure, ABreakWithinARowOfThePeakIsTheWiresAndOneBeforeItABrokenWires)
{
    TriaxialSeries s;
    for (int i = 0; i < 10; ++i) {
        TriaxialSample row;
        row.time_s = 1e-3 * i;
        s.push_back(row);
    }
    const auto at = [](double t) {
        TestWireBreak b;
        b.test_time_s = t;
        return std::vector<TestWireBreak>{b};
    };
    EXPECT_EQ(peak_failure(s, 5, {}), PeakFailure::grains);
    EXPECT_EQ(peak_failure(s, 5, at(5.5e-3)), PeakFailure::wire);
    EXPECT_EQ(peak_failure(s, 5, at(6e-3)), PeakFailure::wire);
    EXPECT_EQ(peak_failure(s, 5, at(4.5e-3)), PeakFailure::wire);
    EXPECT_EQ(peak_failure(s, 5, at(6.5e-3)), PeakFailure::grains) << "a break after the peak's next row";
    EXPECT_EQ(peak_failure(s, 5, at(3e-3)), PeakFailure::grains_after_break);
    EXPECT_STREQ(to_string(PeakFailure::grains_after_break), "grains_after_break");
}
