// Quantities derived from a job: the stable time step against the spring
// formulas of the model spec §4, the body estimate, the damping time.
#include "api/derived.hpp"
#include "api/engine_settings.hpp"

#include "laws/hertz.hpp"
#include "state/clump_shape.hpp"
#include "state/world.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace wiredem::api;

namespace {

/// Critical step of a wire chain without damping: 0.3 / √(4 k_elo / m_w).
double wire_undamped_critical_s(const WireSpec& w, double density_scale)
{
    const double area = std::numbers::pi * w.radius_m * w.radius_m;
    const double k = w.youngs_modulus_pa * area / w.segment_length_m;
    const double m = w.density_kg_per_m3 * area * w.segment_length_m * density_scale;
    return wiredem::engine::gear5_stability_limit / std::sqrt(4.0 * k / m);
}

/// Critical step of the membrane mesh: 0.3 / √(12 k_m / m_m).
double membrane_critical_s(const MembraneSpec& mb, double density_scale)
{
    const double k = std::numbers::sqrt3 / 2.0 * mb.youngs_modulus_pa * mb.thickness_m;
    const double m = std::numbers::sqrt3 / 2.0 * mb.mesh_size_m * mb.mesh_size_m * mb.density_kg_per_m3
                   * mb.thickness_m * density_scale;
    return wiredem::engine::gear5_stability_limit / std::sqrt(12.0 * k / m);
}

} // namespace

TEST(StableStep, DefaultJobIsLimitedByTheWireBelowAMicrosecond)
{
    // The model spec §4: the wire needs δt below about 1 µs.
    // Its highest mode is damped (ζ_w = 0.3): Gear-5's ω δt ≤ 0.065/0.3
    // (engine::damped_stability_limit) sets the critical step, while auto
    // stays half the undamped one (ω δt = 0.15, below the damped bound).
    const StableStep st = stable_time_step(JobSpec{});
    EXPECT_LT(st.critical_s, 1.3e-6);
    EXPECT_EQ(st.limited_by, "wire segments");
    const double undamped = wire_undamped_critical_s(WireSpec{}, 1.0);
    EXPECT_NEAR(st.undamped_critical_s, undamped, 1e-12 * undamped);
    EXPECT_NEAR(st.critical_s, 0.065 / 0.3 / wiredem::engine::gear5_stability_limit * undamped, 1e-12 * undamped);
    EXPECT_DOUBLE_EQ(st.auto_s, wiredem::engine::auto_time_step_fraction * undamped);
}

TEST(StableStep, TheEstimateLeavesTheContactsDampingToTheRun)
{
    // γ_n from a restitution is a fit of 50–250 ms: the estimate made at
    // validation does not compute it (the run's step from the World does,
    // engine tests HertzCollision.HeavilyDamped…). A restitution of 0.05 and
    // of 0.5 give the same estimate.
    JobSpec s;
    s.specimen.wire.pattern = WirePattern::none;
    s.specimen.membrane.youngs_modulus_pa = 1e4; // the contacts set the step
    const StableStep light = stable_time_step(s);
    ASSERT_EQ(light.limited_by.rfind("grain–grain", 0), 0u) << light.limited_by; // the contacts or their springs
    s.contact.normal_damping = NormalRestitution{0.05, 0.1};
    EXPECT_EQ(stable_time_step(s).auto_s, light.auto_s);
}

TEST(StableStep, WithoutWireTheMembraneEdgesLimit)
{
    JobSpec s;
    s.specimen.wire.pattern = WirePattern::none;
    const StableStep st = stable_time_step(s);
    EXPECT_EQ(st.limited_by, "membrane edges");
    EXPECT_NEAR(st.critical_s, membrane_critical_s(MembraneSpec{}, 1.0), 1e-12 * st.critical_s); // undamped
    EXPECT_EQ(st.critical_s, st.undamped_critical_s);
    EXPECT_GT(st.critical_s, stable_time_step(JobSpec{}).critical_s);
}

TEST(StableStep, DensityScalingRaisesTheStepAsItsSquareRoot)
{
    // Every limit is ∝ √m, and scaling multiplies every mass.
    JobSpec s;
    s.engine.density_scale = 100.0;
    EXPECT_NEAR(stable_time_step(s).critical_s, 10.0 * stable_time_step(JobSpec{}).critical_s,
        1e-12 * stable_time_step(s).critical_s);
}

TEST(StableStep, StiffGrainsTakeOverFromASoftWire)
{
    JobSpec s;
    s.specimen.wire.youngs_modulus_pa = 1e6;
    s.specimen.membrane.youngs_modulus_pa = 1e5;
    s.specimen.grain.youngs_modulus_pa = 1e12;
    // The contacts, or at their reference load their tangential springs
    // (docs/model.md, "The tangential and rolling springs in the step").
    EXPECT_EQ(stable_time_step(s).limited_by.rfind("grain–grain", 0), 0u) << stable_time_step(s).limited_by;
}

// A job of clumps: the estimate at the door takes the clump's smallest
// sphere and the mass its contacts see (its mass and inertia), as the
// engine's World does: the door's step is the step of a World holding the
// job's clumps (all of one size: no spread), whatever their orientation.
TEST(StableStep, AClumpJobsEstimateIsTheEnginesStepOfItsClumps)
{
    namespace engine = wiredem::engine;
    JobSpec s;
    s.specimen.wire.pattern = WirePattern::none;
    s.specimen.membrane.youngs_modulus_pa = 1e4; // the grains set the step
    s.specimen.grain.youngs_modulus_pa = 1e11;
    s.specimen.grain_shape = GrainShapeSpec{"tetrahedral", {}};
    const StableStep door = stable_time_step(s);
    // The clumps' contacts set the step, through their tangential springs
    // at the reference load (the sphere's 1/M + (|b| + r)²/I_min).
    ASSERT_EQ(door.limited_by, "grain–grain tangential and rolling springs");

    engine::World w;
    const std::uint8_t grain = engine::add_material(w, engine::Material{s.specimen.grain.youngs_modulus_pa,
        s.specimen.grain.poisson_ratio, s.specimen.grain.density_kg_per_m3});
    const engine::ClumpBody clump
        = engine::scaled_clump(grain_shape_body(*s.specimen.grain_shape), s.specimen.grain_radius_m);
    engine::add_wall(w, engine::make_plate(0.0, +1.0,
        engine::add_material(w, engine::Material{s.specimen.plate.youngs_modulus_pa, s.specimen.plate.poisson_ratio, 7800.0})));
    for (int i = 0; i < 3; ++i)
        engine::add_clump(w, clump, engine::Vec3(0.01 * i, 0.0, 0.01),
            engine::Quat(Eigen::AngleAxisd(0.7 * i, engine::Vec3(1.0, 2.0, 3.0).normalized())), grain);
    const StableStep engine_step = engine::stable_time_step(w);
    EXPECT_EQ(engine_step.limited_by, door.limited_by);
    EXPECT_EQ(door.critical_s, engine_step.critical_s);
    EXPECT_EQ(door.springs_critical_s, engine_step.springs_critical_s);
    EXPECT_EQ(door.undamped_critical_s, engine_step.undamped_critical_s);

    // Spheres of the clumps' volume-equivalent radius (what the door took
    // before) are larger than a clump's spheres (0.808 mm against 1.23 mm)
    // and heavier than what a clump's contact sees: a longer step of the
    // normal contacts. (Their tangential springs bind the other way: a
    // clump's sphere moves sideways less than a lone sphere.)
    JobSpec spheres = s;
    spheres.specimen.grain_shape.reset();
    EXPECT_LT(door.undamped_critical_s, stable_time_step(spheres).undamped_critical_s);
}

TEST(StableStep, ParserAcceptsTheCriticalStepAndRejectsJustAbove)
{
    const double critical_s = stable_time_step(JobSpec{}).critical_s;
    JobSpec at = JobSpec{};
    at.engine.time_step_s = critical_s;
    EXPECT_TRUE(parse_job_spec(to_json(at)).ok());
    JobSpec above = JobSpec{};
    above.engine.time_step_s = critical_s * 1.001;
    const auto parsed = parse_job_spec(to_json(above));
    ASSERT_FALSE(parsed.ok());
    EXPECT_EQ(parsed.error()[0].path, "engine.time_step_s");
}

TEST(BodyCounts, DefaultColumnMatchesTheGeometry)
{
    const BodyCounts n = estimated_body_counts(JobSpec{});
    EXPECT_EQ(n.grains, 8000u);
    // Laid at ω R_a while the grains are poured, up to one grain diameter
    // below the fill: 8000 grains of 1.23 mm at a packing fraction of 0.58
    // fill 85.57 mm of a 20 mm-radius column; rising 83.11 mm takes 0.3324 s
    // at 0.25 m/s; 300 rad/s × 12 mm × 0.3324 s = 1.1966 m of wire over
    // 1.25 mm segments: ⌈957.3⌉ + 1 nodes.
    EXPECT_EQ(n.wire_nodes, 959u);
    // ⌈2π·20 mm / 1.25 mm⌉ = 101 around, ⌈0.12 / (1.25 mm·√3/2)⌉ + 1 = 112 rows.
    EXPECT_EQ(n.membrane_nodes, 101u * 112u);
    EXPECT_EQ(n.total(), 8000u + 959u + 11312u);
}

TEST(BodyCounts, NoWireWithoutPattern)
{
    JobSpec s;
    s.specimen.wire.pattern = WirePattern::none;
    EXPECT_EQ(estimated_body_counts(s).wire_nodes, 0u);
}

TEST(NormalDamping, GivenTimeIsUsedAsIs)
{
    JobSpec s;
    s.contact.normal_damping = NormalDampingTime{3e-6};
    EXPECT_EQ(resolved_normal_damping_s(s), 3e-6);
}

TEST(NormalDamping, RestitutionGivesTheRequestedBounceOfTwoGrains)
{
    JobSpec s;
    s.contact.normal_damping = NormalRestitution{0.7, 0.2};
    const double gamma_s = resolved_normal_damping_s(s);
    EXPECT_GT(gamma_s, 0.0);
    const double r = s.specimen.grain_radius_m;
    const double m = s.specimen.grain.density_kg_per_m3 * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const double e_star = wiredem::engine::effective_modulus_pa(10e9, 0.3, 10e9, 0.3);
    const double e = wiredem::engine::hertz_restitution(0.5 * m, 0.2, e_star, 0.5 * r, gamma_s);
    EXPECT_NEAR(e, 0.7, 1e-4);
}
