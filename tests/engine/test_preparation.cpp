// Specimen preparation on small columns (R = 8 mm, a hundred or so grains),
// every pattern: each prepares in seconds (Release) and must give a sound
// specimen. Quasi-static scaling as in the examples: masses × 100, the wire
// and membrane nodes another × 400, so that neither the nodes' springs nor
// heavy grains' impacts make δt small. A preparation stopped in any phase,
// saved and continued ends as one that never stopped.
#include "contact/geometry.hpp"
#include "core/format.hpp"
#include "io/snapshot.hpp"
#include "small_column.hpp"
#include "specimen/preparation.hpp"
#include "state/clump_shape.hpp"
#include "state/state_hash.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <unistd.h>
#include <vector>

using namespace wiredem::engine;
using wiredem::engine::test::small_column;

namespace {

/// Grains of the sound-column tests: "a few hundred" (issue 5). Until the
/// tangential law's re-stick test (engine/laws/tangential.hpp) piles of more
/// than ~120 did not settle at the auto δt (tests/engine/test_settling.cpp).
constexpr std::size_t test_column_grains = 300;

/// Checks every property a prepared specimen must have.
void expect_sound_specimen(const World& w, const PreparationSpec& spec, const PreparationReport& r)
{
    EXPECT_EQ(r.grains, spec.grain_count);
    // Only the plates are left: the mould is gone.
    ASSERT_EQ(w.walls.size(), 2u);
    ASSERT_EQ(r.top_plate_wall, 1u);
    const Wall& top_plate = w.walls[r.top_plate_wall];
    const double lid = top_plate.point_m.z();
    // Inside the membrane: no centre beyond the inner surface of its node
    // spheres (R − r_m), and no grain reaching past R.
    const double inner_m = spec.membrane_radius_m - spec.membrane.contact_radius_m;
    const TranslationalState& g = w.of(BodyKind::grain);
    for (std::size_t i = 0; i < g.size(); ++i) {
        const Vec3& x = g.x[0][i];
        const double r_i = g.radius_m[i];
        ASSERT_TRUE(x.allFinite());
        EXPECT_GT(x.z(), 0.95 * r_i) << "grain " << i << " below the bottom plate";
        EXPECT_LT(x.z(), lid) << "grain " << i << " above the top plate";
        EXPECT_LT(std::hypot(x.x(), x.y()) + r_i, spec.membrane_radius_m) << "grain " << i << " outside the membrane";
        EXPECT_LT(std::hypot(x.x(), x.y()), inner_m) << "grain " << i << " inside the membrane's wall";
    }
    // The top plate rests on the grains (not on wire standing out of the pile).
    EXPECT_TRUE(w.contacts.wall_touches(r.top_plate_wall, BodyKind::grain)) << "the top plate touches no grain";
    // At rest, no contact overlaps by more than 10 % of the grain radius. The
    // static overlaps are far smaller: the column's weight (masses × 100,
    // weights alike while preparing) on the bottom layer gives
    // (3 F/(4 E* √R*))^{2/3} ≈ 3 µm ≈ 0.3 % r_p; a wire node pressed by the
    // bent wire with ~3 N, ~30 µm.
    const ContactList& c = w.contacts;
    for (std::size_t p = 0; p < c.pair_count(); ++p) {
        if (!c.touching[p]) continue;
        const TranslationalState &A = w.of(c.first[p].kind()), &B = w.of(c.second[p].kind());
        const std::uint32_t a = c.first[p].index(), b = c.second[p].index();
        const double overlap = A.radius_m[a] + B.radius_m[b] - (A.x[0][a] - B.x[0][b]).norm();
        EXPECT_LT(overlap, 0.1 * spec.grain_radius_m) << "contact " << p << " kinds " << int(c.first[p].kind()) << "-"
                                                     << int(c.second[p].kind());
    }
    // The wire is continuous: every segment within 3 % of its rest length
    // (a static 3 N stretches one by 0.4 %); its ends are free again once
    // laid; every node is inside the membrane and between the plates.
    for (double strain : w.wire_forces.segment_strain) EXPECT_LT(std::abs(strain), 0.03);
    const TranslationalState& wire = w.of(BodyKind::wire);
    for (std::size_t i = 0; i < wire.size(); ++i) {
        EXPECT_TRUE(is_dynamic(wire, i)) << "wire node " << i << " still held";
        EXPECT_LT(std::hypot(wire.x[0][i].x(), wire.x[0][i].y()), inner_m) << "wire node " << i << " outside the membrane";
        EXPECT_GT(wire.x[0][i].z(), 0.9 * spec.wire.radius_m) << "wire node " << i << " below the bottom plate";
        EXPECT_LT(wire.x[0][i].z(), lid) << "wire node " << i << " above the top plate";
    }
    // A poured random packing in the core of the column (see
    // core_volume_fractions). Over the whole column (the report's fractions),
    // the walls and the rough top make it lower, and it cannot be denser.
    const double core = r.core_grain_volume_fraction + r.core_wire_volume_fraction;
    EXPECT_GT(core, 0.5);
    EXPECT_LT(core, 0.64);
    EXPECT_GT(r.core_grain_volume_fraction, r.grain_volume_fraction);
    EXPECT_LT(r.grain_volume_fraction + r.wire_volume_fraction, 0.64);
    EXPECT_NEAR(r.sample_volume_m3, std::numbers::pi * spec.membrane_radius_m * spec.membrane_radius_m * r.pile_height_m, 1e-15);
    EXPECT_NEAR(r.pile_height_m, lid, 1e-15);
}

} // namespace

TEST(Preparation, PoursASoundColumnWithoutWire)
{
    const PreparationSpec spec = small_column(PatternKind::none, test_column_grains);
    Simulation sim(1); // results do not depend on it (the determinism tests below)
    const auto r = prepare_specimen(sim, spec);
    ASSERT_TRUE(r.ok()) << r.error();
    expect_sound_specimen(sim.world, spec, r.value());
    EXPECT_EQ(r.value().wire_nodes, 0u);
}

// A column poured from a sieve curve (engine/specimen/grain_sizes.hpp): the
// grains in it reproduce the curve (the report's Kolmogorov–Smirnov distance
// below its 1 % critical value), every one inside the curve's sizes, and the
// column is as sound as one of equal grains.
TEST(PreparationGrainSizes, PoursGrainsThatReproduceTheCurve)
{
    PreparationSpec spec = small_column(PatternKind::none, 200);
    spec.grain_sizes = SieveCurve{SieveCurve::Basis::mass, {1.6e-3, 2.4e-3, 3.2e-3}, {0.0, 0.4, 1.0}};
    Simulation sim(1);
    const auto r = prepare_specimen(sim, spec);
    ASSERT_TRUE(r.ok()) << r.error();
    expect_sound_specimen(sim.world, spec, r.value());
    ASSERT_TRUE(r.value().grain_sizes.has_value());
    const GrainSizeReport& z = *r.value().grain_sizes;
    EXPECT_EQ(z.grains, spec.grain_count);
    EXPECT_LT(z.ks_distance, z.ks_critical_1pct);
    EXPECT_NEAR(z.ks_critical_1pct, 1.628 / std::sqrt(200.0), 1e-3);
    for (double radius : sim.world.of(BodyKind::grain).radius_m) {
        EXPECT_GE(radius, 0.8e-3);
        EXPECT_LE(radius, 1.6e-3);
    }
    // The curve's D10 is its second sieve's log step: P = 0.1 at a quarter
    // of the way from 1.6 to 2.4 mm.
    EXPECT_NEAR(z.requested.d10_m, 1.6e-3 * std::pow(1.5, 0.25), 1e-12);
}

TEST(PreparationClumps, PoursRandomlyTurnedClumpsIntoASoundColumn)
{
    // 60 crushed-gravel clumps (five spheres each) of volume-equivalent
    // radius 1.23 mm: all poured, settled, inside the membrane and between
    // the plates, turned every way (for uniform orientations the mean
    // |cos| of a body axis with the vertical is 1/2).
    PreparationSpec spec = small_column(PatternKind::none, 60);
    spec.grain_shape = unit_clump_shape(*builtin_clump_template("crushed"));
    Simulation sim(1);
    const auto r = prepare_specimen(sim, spec);
    ASSERT_TRUE(r.ok()) << r.error();
    const World& w = sim.world;
    const PreparationReport& report = r.value();
    EXPECT_TRUE(report.settled);
    EXPECT_EQ(report.grains, 60u);
    ASSERT_EQ(w.clumps.size(), 60u);
    EXPECT_EQ(w.of(BodyKind::grain).size(), 300u);
    const double inner = spec.membrane_radius_m - spec.membrane.contact_radius_m;
    const double top = w.walls[report.top_plate_wall].point_m.z();
    const TranslationalState& g = w.of(BodyKind::grain);
    for (std::size_t i = 0; i < g.size(); ++i) {
        EXPECT_LT(g.x[0][i].head<2>().norm() + g.radius_m[i], spec.membrane_radius_m) << "sphere " << i;
        EXPECT_LT(g.x[0][i].head<2>().norm(), inner) << "sphere " << i;
        EXPECT_GE(g.x[0][i].z() - g.radius_m[i], -0.1 * g.radius_m[i]) << "sphere " << i;
        EXPECT_LE(g.x[0][i].z() + g.radius_m[i], top + 0.1 * g.radius_m[i]) << "sphere " << i;
    }
    double mean_cos = 0.0;
    for (const Quat& q : w.clumps.orientation) mean_cos += std::abs((q * Vec3::UnitX()).z()) / 60.0;
    EXPECT_NEAR(mean_cos, 0.5, 0.15);
    // The grains' volume is the clumps' (spheres of the equivalent radius), not the spheres'.
    const double volume = 60.0 * 4.0 / 3.0 * std::numbers::pi * std::pow(spec.grain_radius_m, 3);
    EXPECT_NEAR(report.grain_volume_fraction * report.sample_volume_m3 / volume, 1.0, 1e-9);
}

TEST(Preparation, RefusesADampingNoExplicitStepCanFollow)
{
    // γ_n = 0.1 s: the contacts' damping ratio at the reference overlap is in
    // the thousands, so Gear-5's damped bound is a tiny fraction of the
    // undamped step: refused, naming the damping, instead of running for
    // thousands of times the steps (or blowing up at the undamped step).
    PreparationSpec spec = small_column(PatternKind::none, test_column_grains);
    spec.contact.normal_damping_s = 0.1;
    Simulation sim(1);
    const auto r = prepare_specimen(sim, spec);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("normal damping γ_n = 0.1 s"), std::string::npos) << r.error();
    // (The same column with its own damping prepares: PoursASoundColumnWithoutWire.)
}

TEST(Preparation, RefusesAnExplicitStepAboveThePoursStableLimit)
{
    // The pour's step is bounded at its fastest impact, damping included; an
    // explicit step above it is refused, naming the field, before a step is
    // taken (it used to run and blow up: the gravel job of
    // docs/calibration/gravel/ at engine.time_step_s = 3.4 µs, in 1 s).
    PreparationSpec spec = small_column(PatternKind::none, test_column_grains);
    spec.time_step_s = 1e-3;
    Simulation sim(1);
    const auto r = prepare_specimen(sim, spec);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("engine.time_step_s"), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("exceeds the stable limit"), std::string::npos) << r.error();
}

TEST(Preparation, ABlowUpSaysWhenAndWhatToChange)
{
    // A velocity made NaN between two steps stands for a pour whose step was
    // too large for what it met: the run ends with the step count and time,
    // the step, and the field to change with a value to try (it used to say
    // "time step too large?" and no field).
    PreparationSpec spec = small_column(PatternKind::none, 100);
    Simulation sim(1);
    PreparationContinuation spoil;
    spoil.between_steps = [&](const World&, const PreparationDriverState& s) {
        if (s.steps == 300) set_velocity(sim.world, BodyRef(BodyKind::grain, 0), Vec3::Constant(std::nan("")));
    };
    const auto r = prepare_specimen(sim, spec, RunControl{}, spoil);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("blew up after 301 steps of the preparation, at t = "), std::string::npos) << r.error();
    EXPECT_NE(r.error().find("engine.time_step_s"), std::string::npos) << r.error();
    EXPECT_NE(r.error().find(format_number(sim.world.dt_s) + " s was too large"), std::string::npos) << r.error();
    EXPECT_NE(r.error().find(format_number(0.5 * sim.world.dt_s) + " s (half of it)"), std::string::npos) << r.error();
}

class PreparationWithWire : public ::testing::TestWithParam<PatternKind> {};

TEST_P(PreparationWithWire, LaysTheWireWhilePouringASoundColumn)
{
    const PreparationSpec spec = small_column(GetParam(), test_column_grains);
    Simulation sim(1); // results do not depend on it (the determinism tests below)
    const auto r = prepare_specimen(sim, spec);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_TRUE(r.value().settled);
    expect_sound_specimen(sim.world, spec, r.value());
    // Laid at the path speed ω R_a while pouring (fill height / fill rate),
    // one node per l_w: the node count follows the estimate that
    // engine.max_bodies is checked against within a few nodes.
    const double laid_m = estimated_wire_length_m(spec);
    EXPECT_NEAR(static_cast<double>(r.value().wire_nodes), laid_m / spec.wire.segment_length_m, 0.1 * laid_m / spec.wire.segment_length_m + 3.0);
    // The nozzle fed wire along (nearly) all of its path: it kept up with
    // the pile (at fill rate = v_z^w it does not: 85 nodes of 480 in a
    // paper-size column, which the campaign reports as a warning).
    EXPECT_GT(r.value().wire_length_m, 0.8 * r.value().nozzle_path_m);
    EXPECT_LT(r.value().wire_length_m, r.value().nozzle_path_m + spec.wire.segment_length_m);
    // Every segment near l_w, so the length is (nodes − 1) l_w within 3 %.
    EXPECT_NEAR(r.value().wire_length_m, (r.value().wire_nodes - 1) * spec.wire.segment_length_m,
        0.03 * r.value().wire_length_m);
    // Embedded as the pile grew (the model spec §5): the nozzle starts on the
    // bottom plate and the grains poured after bury what it lays, so part of
    // the wire is still in the bottom layer of grains. (A wire that sprang
    // out of the pile and was pushed back in by the top plate lies in the top
    // layers.)
    const auto& x = sim.world.of(BodyKind::wire).x[0];
    const double lowest = std::min_element(x.begin(), x.end(), [](const Vec3& a, const Vec3& b) { return a.z() < b.z(); })->z();
    EXPECT_LT(lowest, 2.0 * spec.grain_radius_m) << "the wire is not in the bottom layer of grains";
    // The wire keeps the shape it was laid in (plastic joints, docs/model.md,
    // "Wire"). Grains landing on a node push it aside until they fit beside
    // it, by up to r_p + r_w, and in either direction, so the helix's nodes
    // stay on average within r_p of R_a and none is pushed beyond
    // R_a + r_p + r_w. A coil of the specification's elastic wire springs out
    // against the mould instead (measured: nodes up to 7.4 mm from the axis,
    // mean 5.1 mm, for R_a = 4 mm; plastic: mean 3.3 mm, up to 5.5 mm, the coil
    // drawn in where grains kinked it). The radial helix keeps its hairpins: they
    // reach in to 1.7 mm (measured); sprung open, no node came closer than 4.9 mm.
    const double r_a = spec.pattern.helix_radius_m, r_p = spec.grain_radius_m;
    double mean_r = 0.0, min_r = r_a, max_r = 0.0;
    for (const Vec3& p : x) {
        const double r = std::hypot(p.x(), p.y());
        mean_r += r / static_cast<double>(x.size());
        min_r = std::min(min_r, r);
        max_r = std::max(max_r, r);
    }
    if (GetParam() == PatternKind::helix) {
        EXPECT_NEAR(mean_r, r_a, r_p) << "the helix did not keep its radius";
        EXPECT_LT(max_r, r_a + r_p + spec.wire.radius_m) << "the helix sprang out";
    }
    if (GetParam() == PatternKind::radial_helix) {
        EXPECT_LT(min_r, 0.5 * r_a) << "the hairpins sprang open";
    }
}

TEST_P(PreparationWithWire, LaysTheStudysDensityOfWireBuriedAsItGoes)
{
    // The full-size study lays 10 m of wire into 8000 grains (the model spec
    // §9): ~5 % of the column's volume, turns closer than a wire diameter
    // (a helix's pitch 2π v_fill/ω = 0.63 mm). The same density here: 0.35 m
    // into 300 grains (a 20 mm fill; v_fill = 0.06 m/s at ω R_a = 1.2 m/s).
    // The nozzle lays it all, the grains bury it as it goes (it fills the
    // column's height evenly, none of it left on top), and the column is as
    // sound as with less wire.
    constexpr double wire_length_m = 0.35;
    PreparationSpec spec = small_column(GetParam(), test_column_grains);
    spec.fill_rate_m_per_s = fill_rate_for_wire_length_m_per_s(spec, wire_length_m);
    EXPECT_NEAR(estimated_wire_length_m(spec), wire_length_m, 1e-12);
    Simulation sim(1);
    const auto r = prepare_specimen(sim, spec);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_TRUE(r.value().settled);
    expect_sound_specimen(sim.world, spec, r.value());
    // Laid: the nozzle's path is the length asked for, and it was never
    // blocked for more than a few segments.
    EXPECT_NEAR(r.value().nozzle_path_m, wire_length_m, 0.03 * wire_length_m);
    EXPECT_NEAR(r.value().wire_length_m, wire_length_m, 0.03 * wire_length_m);
    EXPECT_GT(r.value().core_wire_volume_fraction, 0.03);
    // Buried as it goes: every third of the height the wire was laid over
    // holds a fair share of the nodes (a third each if even; a mat on top
    // would put most in the last), hardly any lie within a grain diameter of
    // the top plate, and the wire reaches up to where the laying stopped.
    // That is a cover below the fill *estimated* at a packing of 0.58; the
    // poured column is looser (φ, grains and wire, from the report), so the
    // cover stands 0.58/φ times taller, and the rough top and its compaction
    // under the lid add up to two grain diameters. (Thirds of lid − cover
    // instead moved with the pile's height: 1 mm more pile, measured, took
    // the top third past a tenth of the wire.)
    const auto& x = sim.world.of(BodyKind::wire).x[0];
    const double lid = sim.world.walls[r.value().top_plate_wall].point_m.z();
    double wire_top = 0.0;
    for (const Vec3& p : x) wire_top = std::max(wire_top, p.z());
    const double packing = r.value().grain_volume_fraction + r.value().wire_volume_fraction;
    EXPECT_GT(wire_top, lid - wire_cover_height_m(spec) * 0.58 / packing - 4.0 * spec.grain_radius_m)
        << "the wire stops short of the top of the column";
    std::array<std::size_t, 3> thirds{};
    std::size_t on_top = 0;
    for (const Vec3& p : x) {
        thirds[std::min<std::size_t>(2, static_cast<std::size_t>(3.0 * std::max(0.0, p.z()) / wire_top))] += 1;
        if (p.z() > lid - 2.0 * spec.grain_radius_m) ++on_top;
    }
    for (std::size_t k = 0; k < 3; ++k)
        EXPECT_NEAR(static_cast<double>(thirds[k]) / static_cast<double>(x.size()), 1.0 / 3.0, 0.12) << "third " << k;
    EXPECT_LT(static_cast<double>(on_top), 0.05 * static_cast<double>(x.size()));
}

namespace {

/// A quarter of the study's helix column: 2000 grains in R = 20 mm with 2.5 m
/// of helix, the study's wire density, the job's default restitution (0.5
/// at 0.1 m/s between two grains).
PreparationSpec quarter_helix_column(std::uint64_t seed)
{
    PreparationSpec spec;
    spec.membrane_radius_m = 0.02;
    spec.membrane_height_m = 0.045;
    spec.grain_count = 2000;
    spec.pattern.pattern = PatternKind::helix;
    spec.density_scale = 100.0;
    spec.wire_mass_scale = 400.0;
    spec.membrane.density_kg_per_m3 = 20000.0; // as examples/paper-helix.json
    spec.max_time_s = 3.0;
    const double grain_mass = spec.density_scale * spec.grain.density_kg_per_m3 * 4.0 / 3.0 * std::numbers::pi
                            * std::pow(spec.grain_radius_m, 3);
    const double e_star = effective_modulus_pa(spec.grain.youngs_modulus_pa, spec.grain.poisson_ratio,
        spec.grain.youngs_modulus_pa, spec.grain.poisson_ratio);
    spec.contact.normal_damping_s = hertz_damping_for_restitution_s(0.5, 0.5 * grain_mass, 0.1, e_star, 0.5 * spec.grain_radius_m);
    spec.fill_rate_m_per_s = fill_rate_for_wire_length_m_per_s(spec, 2.5);
    spec.seed = seed;
    return spec;
}

} // namespace

TEST(PreparationWithWireEnd, AQuarterOfTheStudysHelixColumnPreparesWithoutTheEndWhipping)
{
    // The nozzle holds the wire's end until the lid rests on the pile.
    // Pinned where it was laid, the end stayed put while the column compacted
    // under it: in this column (a quarter of the study's: 2000 grains in
    // R = 20 mm with 2.5 m of helix, the study's wire density) its last
    // segment was stretched 4.3 times, and released, the end whipped at
    // 30 m/s and the preparation blew up (measured: at step 145 934). Paid out
    // as the column compacts, the end is released unstrained. 2.5–5 minutes of
    // both cores in Release: label study_scale, not run in CI (tests/CMakeLists.txt).
    const PreparationSpec spec = quarter_helix_column(1);
    Simulation sim(2);
    const auto r = prepare_specimen(sim, spec);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_TRUE(r.value().settled);
    EXPECT_NEAR(r.value().wire_length_m, 2.5, 0.03 * 2.5);
    for (double strain : sim.world.wire_forces.segment_strain) EXPECT_LT(std::abs(strain), 0.03);
}

TEST(PreparationLid, LetsGoOfTheHeldWireEndItReaches)
{
    // A node the nozzle holds is prescribed, and a wall's contacts are with
    // bodies that move by their forces only: the lid coming down meets no
    // resistance from it. Released only once the lid met the grains, an end
    // that stuck up above the pile was released inside the lid (this column,
    // seed 1: 0.35 mm deep, 75 N, the end at 1.7 m/s and its last segment 7 %
    // short when the column was declared settled). The nozzle lets go as the
    // lid reaches it: no held node is ever closer to the lid than its radius
    // less the lid's travel in one step. Seeds 1 and 2 both bring the lid to
    // the end (measured: within 0.001 r_w); the test runs seed 1, the column
    // of the failure, and must see the lid reach the end, or it shows nothing
    // (seed 2 as well took 118 s of the CI's Release phase, 2026-12-06).
    // ~45 s of both cores in Release: label physics_long.
    std::size_t reached = 0;
    for (std::uint64_t seed : {1u}) {
        const PreparationSpec spec = quarter_helix_column(seed);
        Simulation sim(2);
        double closest = std::numeric_limits<double>::infinity();
        PreparationContinuation watch;
        watch.between_steps = [&](const World& w, const PreparationDriverState& s) {
            if (s.phase < PreparationPhase::lowering_lid) return;
            const TranslationalState& wire = w.of(BodyKind::wire);
            for (std::size_t i = 0; i < wire.size(); ++i)
                if (!is_dynamic(wire, i))
                    closest = std::min(closest, wall_gap(w.walls[s.top_plate_wall], wire.x[0][i]).gap_m / wire.radius_m[i]);
        };
        const auto r = prepare_specimen(sim, spec, {}, watch);
        ASSERT_TRUE(r.ok()) << r.error();
        EXPECT_TRUE(r.value().settled) << "seed " << seed;
        const double lid_step = spec.plate_speed_m_per_s * sim.world.dt_s / spec.wire.radius_m;
        EXPECT_GE(closest, 1.0 - lid_step) << "seed " << seed;
        if (closest < 1.5) ++reached; // within half a radius of the held node's surface
        for (double strain : sim.world.wire_forces.segment_strain) EXPECT_LT(std::abs(strain), 0.03) << "seed " << seed;
    }
    EXPECT_GT(reached, 0u) << "the lid reached no held end: the test shows nothing";
}

const auto pattern_label = [](const ::testing::TestParamInfo<PatternKind>& i) { return std::string(pattern_name(i.param)); };
INSTANTIATE_TEST_SUITE_P(EveryPattern, PreparationWithWire,
    ::testing::Values(PatternKind::helix, PatternKind::spiral_helix), pattern_label);
// The radial helix: each radial excursion turns the wire by π within two
// joints (legs 2.5 r_w apart). With the specification's straight-rest
// (elastic) bending springs its hairpins sprang open as soon as the nozzle let
// go, the wire stood straight up and the top plate pushed it back into the top
// layers (lowest node 6.8 mm above the floor): it failed the embedding check.
// The nozzle forms the wire plastically (docs/model.md, "Wire"), so the
// hairpins keep their shape and every check passes unchanged. (Kept as its own
// instantiation so that its name stays findable.)
INSTANTIATE_TEST_SUITE_P(RadialHelix, PreparationWithWire, ::testing::Values(PatternKind::radial_helix), pattern_label);

namespace {

/// Whether the nozzle is pushing a node out through the grains round the
/// wire's end: the end kinematic, the node before it held.
bool pushing_out(const World& w)
{
    const TranslationalState& wire = w.of(BodyKind::wire);
    const std::size_t n = wire.size();
    return n >= 2 && wire.motion[n - 1] == Motion::kinematic && !is_dynamic(wire, n - 2);
}

/// The test column with the helix at its fill rate (0.3 m/s), from `seed`.
PreparationSpec helix_column(std::uint64_t seed)
{
    PreparationSpec spec = small_column(PatternKind::helix, test_column_grains);
    spec.seed = seed;
    return spec;
}

} // namespace

TEST(PreparationNozzle, LaysItsWholePathWhateverTheSeed)
{
    // Grains landing round the wire's held end bury it, and a nozzle that
    // only looks upwards and ahead from there for room for the next node
    // stops laying for good. Seeds 4 and 6 of the helix column, measured
    // with such a nozzle (the search over the grain alone) at this step: 16
    // and 25 nodes of 57. Two segments late, the nozzle looks round the
    // grains, and with no way clear it pushes the wire out through them
    // (seed 6 does, four times). It lays its path but for the segment not yet
    // due (< l) and the path it runs while a node is pushed out (at most
    // 0.95 l at v_z^w, while the nozzle moves on at ω R_a).
    for (std::uint64_t seed : {4u, 6u}) {
        const PreparationSpec spec = helix_column(seed);
        Simulation sim(1);
        const auto r = prepare_specimen(sim, spec);
        ASSERT_TRUE(r.ok()) << r.error();
        EXPECT_TRUE(r.value().settled) << "seed " << seed;
        expect_sound_specimen(sim.world, spec, r.value());
        const double l = spec.wire.segment_length_m;
        const double pushed_path = spec.pattern.angular_speed_rad_per_s * spec.pattern.helix_radius_m * 0.95 * l
                                 / spec.pattern.nozzle_rise_speed_m_per_s;
        EXPECT_GT(r.value().wire_length_m, r.value().nozzle_path_m - l - pushed_path) << "seed " << seed;
        EXPECT_LT(r.value().wire_length_m, r.value().nozzle_path_m + l) << "seed " << seed;
    }
}

TEST(PreparationNozzle, APushStoppedHalfWayContinuesBitIdentically)
{
    // Seed 6 of the helix column pushes a node out from about step 6 800 for
    // some 580 steps (l / (v_z^w δt)). Saved 100 steps into that push and
    // continued on two threads, it is at step 10 000 where the run that was
    // never stopped is: whether a node is coming out is read from the World
    // (the end kinematic, the node before it held), not kept by the driver.
    const PreparationSpec spec = helix_column(6);
    constexpr std::uint64_t compare_at = 10'000;
    const std::filesystem::path file = std::filesystem::temp_directory_path()
                                     / ("wiredem_nozzle_push_" + std::to_string(::getpid()) + ".h5");
    std::optional<PreparationDriverState> saved;
    std::uint64_t pushing_for = 0, whole_hash = 0;
    {
        Simulation whole(1);
        std::atomic<bool> cancel{false};
        RunControl control;
        control.cancel = &cancel;
        PreparationContinuation watch;
        watch.between_steps = [&](const World& w, const PreparationDriverState& s) {
            pushing_for = pushing_out(w) ? pushing_for + 1 : 0;
            if (pushing_for == 100 && !saved) {
                ASSERT_TRUE(save_snapshot(w, file).ok());
                saved = s;
            }
            if (s.steps == compare_at) {
                whole_hash = state_hash(w);
                cancel = true;
            }
        };
        const auto r = prepare_specimen(whole, spec, control, watch);
        ASSERT_FALSE(r.ok());
        ASSERT_EQ(r.error(), "cancelled");
    }
    ASSERT_TRUE(saved) << "no push by step " << compare_at;
    ASSERT_LT(saved->steps, compare_at);
    Simulation sim(2);
    auto w = restore_snapshot(file);
    ASSERT_TRUE(w.ok()) << w.error();
    sim.world = std::move(w.value());
    ASSERT_TRUE(pushing_out(sim.world));
    std::atomic<bool> cancel{false};
    RunControl control;
    control.cancel = &cancel;
    PreparationContinuation c;
    c.from = saved;
    std::uint64_t continued_hash = 0;
    c.between_steps = [&](const World& w, const PreparationDriverState& s) {
        if (s.steps != compare_at) return;
        continued_hash = state_hash(w);
        cancel = true;
    };
    const auto r = prepare_specimen(sim, spec, control, c);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error(), "cancelled");
    EXPECT_EQ(continued_hash, whole_hash);
    std::filesystem::remove(file);
}

/// A short preparation for the determinism tests: the pour, the laying,
/// some settling, the lid, the release of the wire's end and the lid again,
/// on 30 grains in a membrane just tall enough (its rigid nodes are most of
/// the bodies), for 0.06 s of simulated time (the sanitizer runs are slow).
/// Poured slowly enough to come in three batches, so that the nozzle lays
/// ~20 nodes while the grains land.
PreparationSpec short_preparation(PatternKind kind)
{
    PreparationSpec spec = small_column(kind, 30);
    spec.membrane_height_m = 0.02;
    spec.fill_rate_m_per_s = 0.1;
    spec.max_time_s = 0.06;
    spec.wire_cover_m = 0.0; // 30 grains fill 2 mm, less than the default cover of a grain diameter
    return spec;
}

TEST(Preparation, SameSeedGivesTheSameWireSpecimenOnAnyThreadCount)
{
    const PreparationSpec spec = short_preparation(PatternKind::spiral_helix);
    Simulation one(1), three(3);
    const auto r1 = prepare_specimen(one, spec);
    ASSERT_TRUE(r1.ok()) << r1.error();
    ASSERT_GT(r1.value().wire_nodes, 10u);
    const auto r3 = prepare_specimen(three, spec);
    ASSERT_TRUE(r3.ok()) << r3.error();
    EXPECT_EQ(state_hash(one.world), state_hash(three.world));
}

TEST(Preparation, SameSeedGivesTheSameSpecimenOnAnyThreadCount)
{
    const PreparationSpec spec = short_preparation(PatternKind::none);
    Simulation one(1), three(3);
    ASSERT_TRUE(prepare_specimen(one, spec).ok());
    ASSERT_TRUE(prepare_specimen(three, spec).ok());
    EXPECT_EQ(state_hash(one.world), state_hash(three.world));
    PreparationSpec other = spec;
    other.seed = 2;
    Simulation again(1);
    ASSERT_TRUE(prepare_specimen(again, other).ok());
    EXPECT_NE(state_hash(again.world), state_hash(one.world));
}

namespace {

/// Every number of two reports but the wall time, bit for bit.
void expect_same_report(const PreparationReport& a, const PreparationReport& b)
{
    EXPECT_EQ(a.grains, b.grains);
    EXPECT_EQ(a.wire_nodes, b.wire_nodes);
    EXPECT_EQ(a.wire_length_m, b.wire_length_m);
    EXPECT_EQ(a.nozzle_path_m, b.nozzle_path_m);
    EXPECT_EQ(a.pile_height_m, b.pile_height_m);
    EXPECT_EQ(a.sample_volume_m3, b.sample_volume_m3);
    EXPECT_EQ(a.grain_volume_fraction, b.grain_volume_fraction);
    EXPECT_EQ(a.wire_volume_fraction, b.wire_volume_fraction);
    EXPECT_EQ(a.core_grain_volume_fraction, b.core_grain_volume_fraction);
    EXPECT_EQ(a.core_wire_volume_fraction, b.core_wire_volume_fraction);
    EXPECT_EQ(a.simulated_time_s, b.simulated_time_s);
    EXPECT_EQ(a.steps, b.steps);
    EXPECT_EQ(a.time_step_s, b.time_step_s);
    EXPECT_EQ(a.settled, b.settled);
    EXPECT_EQ(a.top_plate_wall, b.top_plate_wall);
}

} // namespace

// The short wire preparation stopped at two points of every phase (the first
// step there and half-way through it), one after another: each time saved
// (io/snapshot.hpp), restored into a fresh World and continued on another
// thread count from the driver's state. It ends with the specimen and the
// report of the preparation that was never stopped.
TEST(PreparationContinuation, APreparationStoppedInEveryPhaseEndsBitIdentically)
{
    const PreparationSpec spec = short_preparation(PatternKind::spiral_helix);
    // The uninterrupted preparation, and the phase at each point between steps.
    Simulation whole(2);
    std::map<PreparationPhase, std::vector<std::uint64_t>> between_steps_in;
    PreparationContinuation watch;
    watch.between_steps = [&](const World&, const PreparationDriverState& s) { between_steps_in[s.phase].push_back(s.steps); };
    const auto uninterrupted = prepare_specimen(whole, spec, {}, watch);
    ASSERT_TRUE(uninterrupted.ok()) << uninterrupted.error();
    ASSERT_GT(uninterrupted.value().wire_nodes, 10u);
    std::set<std::uint64_t> stops;
    for (const auto& [phase, steps] : between_steps_in) {
        stops.insert(steps.front());
        stops.insert(steps[steps.size() / 2]);
    }
    // Every phase but the lid's following (the lid may rest on the grains
    // already when the column has settled under it) has steps here.
    for (PreparationPhase p : {PreparationPhase::pouring, PreparationPhase::settling, PreparationPhase::lowering_lid,
             PreparationPhase::settling_under_lid})
        EXPECT_TRUE(between_steps_in.contains(p)) << "no step in phase " << static_cast<int>(p);

    const std::filesystem::path file = std::filesystem::temp_directory_path()
                                     / ("wiredem_preparation_continuation_" + std::to_string(::getpid()) + ".h5");
    std::optional<PreparationDriverState> saved;
    std::size_t run = 0;
    constexpr unsigned threads[] = {1, 3, 2};
    for (auto stop = stops.begin();; ++stop, ++run) {
        Simulation sim(threads[run % 3]);
        std::atomic<bool> cancel{false};
        RunControl control;
        control.cancel = &cancel;
        PreparationContinuation c;
        if (saved) {
            auto w = restore_snapshot(file);
            ASSERT_TRUE(w.ok()) << w.error();
            sim.world = std::move(w.value());
            c.from = saved;
        }
        if (stop != stops.end())
            c.between_steps = [&](const World& w, const PreparationDriverState& s) {
                if (s.steps != *stop) return;
                ASSERT_TRUE(save_snapshot(w, file).ok());
                saved = s;
                cancel = true;
            };
        const auto r = prepare_specimen(sim, spec, control, c);
        if (stop == stops.end()) {
            ASSERT_TRUE(r.ok()) << r.error();
            EXPECT_EQ(state_hash(sim.world), state_hash(whole.world));
            expect_same_report(r.value(), uninterrupted.value());
            break;
        }
        ASSERT_FALSE(r.ok()) << "not stopped at step " << *stop;
        EXPECT_EQ(r.error(), "cancelled");
        ASSERT_TRUE(saved && saved->steps == *stop);
    }
    EXPECT_EQ(run, stops.size());
    std::filesystem::remove(file);
}

TEST(Preparation, RejectsAPatternThatDoesNotFitInsideTheMembrane)
{
    PreparationSpec spec = small_column(PatternKind::spiral_helix, 10);
    spec.pattern.helix_radius_m = 6e-3; // R_a + R_i + r_w + clearance = 9 mm > 8 mm
    Simulation sim(1);
    const auto r = prepare_specimen(sim, spec);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("must stay below the membrane radius less the membrane nodes' contact radius"),
        std::string::npos) << r.error();
}

TEST(Preparation, RejectsAFillRateTheNozzleCannotFollow)
{
    PreparationSpec spec = small_column(PatternKind::helix, 150);
    spec.fill_rate_m_per_s = 0.61 * spec.pattern.nozzle_rise_speed_m_per_s; // at most 0.6 ×
    Simulation sim(1);
    const auto r = prepare_specimen(sim, spec);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("too fast for the nozzle"), std::string::npos) << r.error();
}

// Ten grains fill 0.67 mm of the 8 mm membrane, less than the cover of one
// largest diameter poured over the wire's end (2.46 mm): the nozzle would
// stop before laying anything, so the preparation refuses the pattern.
// (It used to lay a wire of one or two nodes.) A fill above the cover is
// prepared.
TEST(Preparation, RefusesAWireWhenTheGrainsDoNotRiseAboveItsCover)
{
    PreparationSpec spec = small_column(PatternKind::helix, 10);
    ASSERT_LT(estimated_fill_height_m(spec), wire_cover_height_m(spec));
    EXPECT_LT(wire_laying_height_m(spec), 0.0);
    EXPECT_EQ(estimated_wire_length_m(spec), 0.0);
    Simulation sim(1);
    const auto r = prepare_specimen(sim, spec);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("the nozzle would lay no wire"), std::string::npos) << r.error();
    EXPECT_FALSE(preparation_error(small_column(PatternKind::helix, 150)).has_value());
    spec.pattern.pattern = PatternKind::none;
    EXPECT_FALSE(preparation_error(spec).has_value());
}
