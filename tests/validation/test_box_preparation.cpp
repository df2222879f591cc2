// The box preparation for the rigid-wall cell (engine/specimen/
// box_preparation.hpp): grains placed at random in a loose box, compacted
// isotropically by the cell's servo walls to σ_c until at rest. Checked: the
// walls hold σ_c within the servo's tolerance at the end (and the fixed
// bottom, which no servo drives, agrees with the top); no overlap beyond the
// Hertz overlap of a force far above the packing's mean contact force; the
// friction during the compaction sets the density (the property the
// preparation is for); the same bits on 1 and 2 threads and for the same
// seed (the reason it needs no checkpoint); bad settings named.
#include "laws/hertz.hpp"
#include "specimen/box_preparation.hpp"
#include "state/clump_shape.hpp"
#include "state/materials.hpp"
#include "state/state_hash.hpp"
#include "triaxial/sampling.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <numbers>

using namespace wiredem::engine;

namespace {

constexpr double sigma_c_pa = 20e3;

/// 200 of the paper's grains (r = 1.23 mm, E = 10 GPa, steel) with the
/// contact law's μ = 0.3 and e ≈ 0.5, compacted to 20 kPa.
BoxPreparationSpec box_spec(std::optional<double> compaction_mu = std::nullopt)
{
    BoxPreparationSpec s;
    s.grain_count = 200;
    s.grain_radius_m = 1.23e-3;
    s.grain_radius_spread = 0.1;
    s.consolidation_pressure_pa = sigma_c_pa;
    s.compaction_friction_coeff = compaction_mu;
    const double m = sphere_mass_kg(s.grain.density_kg_per_m3, s.grain_radius_m);
    const double e_star = effective_modulus_pa(
        s.grain.youngs_modulus_pa, s.grain.poisson_ratio, s.grain.youngs_modulus_pa, s.grain.poisson_ratio);
    s.contact.normal_damping_s = hertz_damping_for_restitution_s(0.5, 0.5 * m, 0.1, e_star, 0.5 * s.grain_radius_m);
    return s;
}

struct BoxRun {
    BoxPreparationReport report;
    World world;
};

BoxRun run_box(const BoxPreparationSpec& spec, unsigned threads = 1)
{
    Simulation sim(threads);
    auto r = prepare_box_specimen(sim, spec);
    EXPECT_TRUE(r.ok()) << (r.ok() ? std::string() : r.error());
    if (!r.ok()) return {};
    return {r.value(), sim.world};
}

/// The default box (μ_c the law's), once per process.
const BoxRun& box_run()
{
    static const BoxRun run = run_box(box_spec());
    return run;
}

} // namespace

TEST(BoxPreparation, WallsHoldTheConsolidationStressAtRest)
{
    const BoxRun& run = box_run();
    const BoxPreparationReport& r = run.report;
    ASSERT_TRUE(r.at_rest) << "after " << r.simulated_time_s << " s";
    const double tol = box_spec().stress_tolerance;
    // The servo's criterion was met at the last check, on the state the
    // report reads.
    EXPECT_NEAR(r.box.sigma_z_pa / sigma_c_pa, 1.0, tol);
    for (const double s : r.box.lateral_pa) EXPECT_NEAR(s / sigma_c_pa, 1.0, tol);
    EXPECT_LE(r.unbalanced_force_ratio, box_spec().unbalanced_force_ratio);
    // The fixed bottom carries what the top does: the grains' net force is
    // at most the unbalanced ratio × the mean contact force per grain, far
    // below the tolerance of the wall's total (≈ 3 % of its force here).
    const double bottom_pa = plate_compression_n(run.world, r.walls.bottom) / (r.box.width_x_m * r.box.width_y_m);
    EXPECT_NEAR(bottom_pa / sigma_c_pa, 1.0, 2 * tol);
    // Compacted: denser than the loose box, and within the range of random
    // packings of spheres against walls (loose 0.55 … close 0.64).
    EXPECT_LT(r.sample_volume_m3, 0.5 * r.initial_volume_m3);
    EXPECT_GT(r.grain_volume_fraction, 0.5);
    EXPECT_LT(r.grain_volume_fraction, 0.65);
    // Isotropic: the box keeps its shape (a cube) to within a grain.
    EXPECT_NEAR(r.box.height_m, r.box.width_x_m, 2 * 1.23e-3);
    EXPECT_NEAR(r.box.width_y_m, r.box.width_x_m, 2 * 1.23e-3);
    EXPECT_EQ(run.world.gravity_m_per_s2, Vec3::Zero());
    EXPECT_EQ(run.world.contact.tangential.friction_coeff, 0.3); // the law's μ again
}

TEST(BoxPreparation, NoOverlapBeyondTheHertzOverlapOfTwentyTimesTheMeanForce)
{
    // The mean contact force of a packing at σ_c: σ = (1/V) Σ l f with
    // l ≈ 2r, N Z/2 contacts and V = N (4/3) π r³/φ gives F̄ = 4π r² σ/(φ Z)
    // ≈ σ (2r)² (φ ≈ 0.6, Z ≈ 5). Contact forces in a packing fall off
    // exponentially above F̄ (a few × F̄ at most in a few hundred grains);
    // 20 F̄ bounds them, and a servo overshoot or a blow-up would break it.
    const BoxPreparationReport& r = box_run().report;
    const BoxPreparationSpec s = box_spec();
    const double r_max = s.grain_radius_m * (1 + s.grain_radius_spread);
    const double force_n = 20 * sigma_c_pa * 4 * r_max * r_max;
    // Hertz at rest: F = (4/3) E* √R* ξ^{3/2}. Between two grains R* = r/2;
    // against a wall R* = r, but the walls are ten times softer (E = 1 GPa),
    // so a wall contact has the larger overlap for a force (measured: the
    // largest overlaps are at the walls, 6.7 µm at 4.8 F̄).
    auto overlap_m = [&](const Material& other, double r_star) {
        const double e_star =
            effective_modulus_pa(s.grain.youngs_modulus_pa, s.grain.poisson_ratio, other.youngs_modulus_pa, other.poisson_ratio);
        return std::pow(3 * force_n / (4 * e_star * std::sqrt(r_star)), 2.0 / 3.0);
    };
    const double xi_bound = std::max(overlap_m(s.grain, 0.5 * r_max), overlap_m(s.wall, r_max));
    EXPECT_GT(r.max_overlap_m, 0.0);
    EXPECT_LE(r.max_overlap_m, xi_bound);
    EXPECT_LT(xi_bound, 0.02 * r_max); // and that bound is small: ≈ 15 µm, 1.1 % of r
}

TEST(BoxPreparation, LessFrictionWhileCompactingPacksDenser)
{
    // At rest here means an unbalanced force ratio of 0.02: the frictional
    // packing creeps on for 0.3 s of simulated time between 0.02 and 0.01
    // while its volume fraction changes by 0.001 (measured, 200 grains).
    auto at = [](double mu_c) {
        BoxPreparationSpec s = box_spec(mu_c);
        s.unbalanced_force_ratio = 0.02;
        return run_box(s);
    };
    const BoxRun frictionless = at(0.0);
    const BoxRun frictional = at(0.5);
    ASSERT_TRUE(frictionless.report.at_rest);
    ASSERT_TRUE(frictional.report.at_rest);
    // Random close packing against random loose packing: 0.64 against ~0.56
    // in bulk; with the walls' looser layers in a box of 200 grains both are
    // lower (measured 0.550 and 0.514), the gap stays.
    EXPECT_GT(frictionless.report.grain_volume_fraction, frictional.report.grain_volume_fraction + 0.025)
        << frictionless.report.grain_volume_fraction << " vs " << frictional.report.grain_volume_fraction;
    // Both under the law's μ again.
    EXPECT_EQ(frictionless.world.contact.tangential.friction_coeff, 0.3);
}

TEST(BoxPreparation, SameBitsOnOneAndTwoThreadsAndForTheSameSeed)
{
    const BoxRun& one = box_run();
    const BoxRun two = run_box(box_spec(), 2);
    EXPECT_EQ(state_hash(two.world), state_hash(one.world));
    EXPECT_EQ(two.report.steps, one.report.steps);
    EXPECT_EQ(two.report.grain_volume_fraction, one.report.grain_volume_fraction);
    // Another seed, another packing (the hash can tell them apart).
    BoxPreparationSpec other = box_spec();
    other.seed = 2;
    other.max_time_s = 1e-4;
    BoxPreparationSpec same = box_spec();
    same.max_time_s = 1e-4;
    EXPECT_NE(state_hash(run_box(other).world), state_hash(run_box(same).world));
    EXPECT_EQ(state_hash(run_box(same).world), state_hash(run_box(same).world));
}

TEST(BoxPreparation, RejectsSettingsOutOfRangeNamingTheField)
{
    struct Case { const char* field; void (*set)(BoxPreparationSpec&); };
    const Case cases[] = {
        {"grain_count", [](BoxPreparationSpec& s) { s.grain_count = 0; }},
        {"initial_packing_fraction", [](BoxPreparationSpec& s) { s.initial_packing_fraction = 0.5; }},
        {"aspect_ratio", [](BoxPreparationSpec& s) { s.aspect_ratio = 0.0; }},
        {"consolidation_pressure_pa", [](BoxPreparationSpec& s) { s.consolidation_pressure_pa = -1.0; }},
        {"compaction_friction_coeff", [](BoxPreparationSpec& s) { s.compaction_friction_coeff = std::nan(""); }},
        {"servo_relaxation", [](BoxPreparationSpec& s) { s.servo_relaxation = 1.5; }},
        {"max_wall_speed_m_per_s", [](BoxPreparationSpec& s) { s.max_wall_speed_m_per_s = 0.0; }},
    };
    for (const Case& c : cases) {
        BoxPreparationSpec s = box_spec();
        c.set(s);
        const auto e = box_preparation_error(s);
        ASSERT_TRUE(e.has_value()) << c.field;
        EXPECT_EQ(e->rfind(c.field, 0), 0u) << *e;
        Simulation sim(1);
        const auto r = prepare_box_specimen(sim, s);
        ASSERT_FALSE(r.ok()) << c.field;
        EXPECT_EQ(r.error(), *e);
    }
}

TEST(BoxPreparation, APreparedBoxRunsThroughTheCuboidCell)
{
    // The chain a cuboid job takes: the default box (μ = 0.3, at 20 kPa),
    // then run_cuboid_triaxial at σ₃ = σ_c, loaded at ε̇ ≈ 0.8/s
    // (I = ε̇ d √(ρ/σ₃) ≈ 10⁻³, quasi-static) to 4 %. A packing of frictional
    // spheres has a peak stress ratio above 1 (sin φ = (σ₁ − σ₃)/(σ₁ + σ₃)
    // > 0) and below the frictionless-wall closed form of Thornton's densest
    // array at μ = 0.3 (σ₁/σ₃ = 3.71: no random packing of these spheres is
    // stronger than the FCC array loaded along its axis). Measured: 1.885 at
    // ε_a = 3.9 % (still rising: a loose packing, φ ≈ 0.54), the lateral
    // walls 1.9 % off σ₃ on average, 4.3 % at most; 102 159 steps, 6 s.
    const BoxRun& box = box_run();
    ASSERT_TRUE(box.report.at_rest);
    Simulation sim(1);
    sim.world = box.world;
    CuboidSettings s;
    s.triaxial.confining_pressure_pa = sigma_c_pa;
    s.triaxial.pressure_ramp_time_s = 0.0; // the box is at σ₃ already
    s.triaxial.hold_time_s = 2e-3;
    s.triaxial.consolidation = Consolidation::cell_pressure;
    s.triaxial.plate_speed_m_per_s = 0.8 * box.report.box.height_m;
    s.triaxial.target_axial_strain = 0.04;
    s.triaxial.sample_interval_s = 2e-4;
    s.triaxial.snapshot_strains = {};  // 0 and the target only, as before the job's defaults
    const auto r = run_cuboid_triaxial(sim, box.report.walls, s);
    ASSERT_TRUE(r.ok()) << r.error();
    const TriaxialResult& t = r.value().triaxial;
    EXPECT_NEAR(t.series.axial_strain.back(), 0.04, 1e-3);
    const double ratio = t.peak_sigma1_pa / t.peak_sigma3_effective_pa;
    EXPECT_GT(ratio, 1.2) << ratio;
    EXPECT_LT(ratio, 2.0 * 1.3 / 0.7) << ratio;
    // The lateral walls held σ₃ while the top loaded (the cell's own band:
    // CuboidCell.ServoHoldsSigma3WithinItsBand).
    EXPECT_LT(r.value().servo_mean_deviation, 0.05) << r.value().servo_mean_deviation;
}

TEST(BoxPreparation, TakesThePouredGrainsAndTheirShape)
{
    PreparationSpec poured;
    poured.grain_count = 123;
    poured.grain_radius_m = 2e-3;
    poured.grain_radius_spread = 0.2;
    poured.grain_sizes = SieveCurve{SieveCurve::Basis::mass, {1e-3, 4e-3}, {0.0, 1.0}};
    poured.density_scale = 100.0;
    poured.contact.tangential.friction_coeff = 0.45;
    poured.seed = 77;
    poured.max_time_s = 3.5;
    const auto box = box_preparation_from(poured, 30e3, 0.1);
    ASSERT_TRUE(box.ok()) << box.error();
    EXPECT_EQ(box.value().grain_count, 123u);
    EXPECT_EQ(box.value().grain_radius_m, 2e-3);
    EXPECT_EQ(box.value().grain_radius_spread, 0.2);
    EXPECT_EQ(box.value().grain_sizes, poured.grain_sizes);
    EXPECT_EQ(box.value().grain.density_kg_per_m3, 100.0 * poured.grain.density_kg_per_m3);
    EXPECT_EQ(box.value().contact.tangential.friction_coeff, 0.45);
    EXPECT_EQ(box.value().seed, 77u);
    EXPECT_EQ(box.value().max_time_s, 3.5);
    EXPECT_EQ(box.value().consolidation_pressure_pa, 30e3);
    EXPECT_EQ(box.value().wall_friction_coeff, 0.1);
    EXPECT_FALSE(box.value().grain_shape.has_value());
    poured.grain_shape = unit_clump_shape(*builtin_clump_template("crushed"));
    const auto clumps = box_preparation_from(poured, 30e3, 0.1);
    ASSERT_TRUE(clumps.ok()) << clumps.error();
    ASSERT_TRUE(clumps.value().grain_shape.has_value());
    EXPECT_EQ(clumps.value().grain_shape->spheres.size(), 5u);
    EXPECT_EQ(clumps.value().grain_shape->volume_m3, poured.grain_shape->volume_m3);
}

// Clumps in the box (the gravel's grains, issue 40): 60 crushed clumps of
// r = 1.23 mm (volume-equivalent) placed where their bounding spheres (1.43 r)
// are free, turned at random, compacted to σ_c. The grains are the clumps:
// 60 of them, 300 spheres; at rest with the walls at σ_c and the unbalanced
// force ratio (of the clumps' net forces, their spheres carry the contacts)
// below its bound; the grains' volume fraction that of the clumps'
// volume-equivalent spheres; the same bits on 1 and 2 threads.
TEST(BoxPreparation, ClumpsArePlacedTurnedAndCompactedAsTheirOwnGrains)
{
    BoxPreparationSpec spec = box_spec();
    spec.grain_count = 60;
    spec.grain_radius_spread = 0.0;
    spec.grain_shape = unit_clump_shape(*builtin_clump_template("crushed"));
    const BoxRun one = run_box(spec);
    const BoxPreparationReport& r = one.report;
    ASSERT_TRUE(r.at_rest) << "after " << r.simulated_time_s << " s";
    EXPECT_EQ(r.grains, 60u);
    EXPECT_EQ(one.world.clumps.size(), 60u);
    EXPECT_EQ(one.world.of(BodyKind::grain).size(), 300u);
    EXPECT_EQ(grain_body_count(one.world), 60u);
    for (const double sigma : r.box.lateral_pa) EXPECT_NEAR(sigma / sigma_c_pa, 1.0, spec.stress_tolerance);
    EXPECT_NEAR(r.box.sigma_z_pa / sigma_c_pa, 1.0, spec.stress_tolerance);
    EXPECT_LE(r.unbalanced_force_ratio, spec.unbalanced_force_ratio);
    EXPECT_DOUBLE_EQ(r.unbalanced_force_ratio, unbalanced_force_ratio(one.world));
    const double grain_volume_m3 = 60.0 * 4.0 / 3.0 * std::numbers::pi * std::pow(spec.grain_radius_m, 3);
    EXPECT_NEAR(r.grain_volume_fraction, grain_volume_m3 / r.sample_volume_m3, 1e-12);
    // Random orientations: no two clumps turned alike.
    EXPECT_NE(one.world.clumps.orientation[0].coeffs(), one.world.clumps.orientation[1].coeffs());
    const BoxRun two = run_box(spec, 2);
    EXPECT_EQ(state_hash(two.world), state_hash(one.world));
    EXPECT_EQ(two.report.steps, one.report.steps);
}

// A wide grading places some of its largest grains late, where random
// sequential addition at the default fraction finds them no room: 1000 of the
// gravel preset's crushed clumps (8/32 curve scaled to D50 = 2 mm) found
// none for grain 829 at 0.25. The box is then made a fifth looser at a time
// until every grain has its place (the compaction closes it anyway); a
// narrow grading keeps the spec's fraction.
TEST(BoxPreparation, AWideGradingIsPlacedInALooserBoxNotRefused)
{
    BoxPreparationSpec spec = box_spec();
    spec.grain_count = 1000;
    spec.grain_radius_m = 1e-3;
    spec.grain_sizes = SieveCurve{SieveCurve::Basis::mass, {0.88e-3, 1.23e-3, 1.76e-3, 2.46e-3, 3.52e-3},
        {0.0, 0.15, 0.4, 0.7, 1.0}};
    spec.grain_shape = unit_clump_shape(*builtin_clump_template("crushed"));
    spec.max_time_s = 1e-5; // the placing only
    const BoxRun run = run_box(spec);
    const double f = run.report.initial_packing_fraction;
    EXPECT_LT(f, spec.initial_packing_fraction);
    const double k = std::log(f / spec.initial_packing_fraction) / std::log(0.8); // f = 0.25 · 0.8^k
    EXPECT_NEAR(k, std::round(k), 1e-9) << f;
    EXPECT_EQ(run.world.clumps.size(), 1000u);
    EXPECT_EQ(box_run().report.initial_packing_fraction, box_spec().initial_packing_fraction);
}
