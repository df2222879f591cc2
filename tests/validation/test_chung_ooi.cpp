// The eight particle-impact benchmarks of Chung & Ooi (Granular Matter 13,
// 2011), run through the whole engine for sphere–sphere, sphere–plate and
// sphere–membrane-node contacts, each against its closed form
// (docs/validation.md says what each checks and where the paper's tangential
// law differs from the Mindlin–Deresiewicz law the benchmark assumes).
//
// Tolerances, from the theory:
// * normal impacts: the Hertz extremes sampled once per step, t_c/2000 apart
//   (the overlap's maximum is flat there: error ~ (π/2000)², nil), and the
//   integrators' error at that step, ~10⁻⁴ of the energy (HertzCollision.*):
//   1e-3 on the overlap, force, speeds and energy; the contact time counted in
//   whole steps: 2 steps of 2000;
// * oblique impacts that slide throughout: the friction impulse is μ J_n
//   whatever the tangential stiffness, short of the spring phase at the start
//   (spring_phase_shortfall, computed per case, ≤ 10⁻⁴ here), of what a
//   finite contact changes (finite_contact_tolerance: the normal turning as
//   the bodies pass, the lever arm r − ξ/2), and of 2e-3 for the normal
//   impulse and the step;
// * impacts that end sticking depend on the tangential law (docs/validation.md):
//   checked only for what any law must give, no energy created.
#include "impact.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace wiredem::engine;
using namespace wiredem::engine::validation;

namespace {

// The benchmarks' materials (Chung & Ooi, Table 1).
const Material glass{4.8e10, 0.20, 2800.0};
const Material limestone{2.0e10, 0.25, 2500.0};
const Material aluminium_alloy{7.0e10, 0.33, 2700.0};
const Material magnesium_alloy{4.0e10, 0.35, 1800.0};
const Material aluminium_oxide{3.8e11, 0.23, 4000.0};
const Material cast_iron{1.0e11, 0.25, 7000.0};
/// The benchmarks' "rigid" plate: the sphere's material, 1000 times stiffer.
Material rigid(const Material& m) { return {1e3 * m.youngs_modulus_pa, m.poisson_ratio, m.density_kg_per_m3}; }
// The paper's grain and membrane (model spec §2): node mass (√3/2) l_m² ρ_m d.
const Material paper_grain{10e9, 0.3, 7800.0};
const Material paper_membrane{0.1e9, 0.0, 1000.0};
constexpr double paper_grain_radius_m = 1.23e-3;
constexpr double paper_node_radius_m = 0.5e-3;
const double paper_node_mass_kg = std::sqrt(3.0) / 2.0 * 1.25e-3 * 1.25e-3 * 1000.0 * 1e-3;

constexpr double tight = 1e-3;

class ChungOoi : public ::testing::TestWithParam<Integrator> {
protected:
    ImpactCase with_integrator(ImpactCase c) const
    {
        c.integrator = GetParam();
        return c;
    }
};

/// A head-on impact against Hertz's closed forms: the largest overlap and
/// force, the contact time, the rebound speed and (undamped) the energy.
void expect_hertz(const ImpactCase& c, const ImpactResult& r)
{
    const PairConstants pc = pair_constants(c);
    const double xi = hertz_max_overlap_m(pc.reduced_mass_kg, pc.approach_speed_m_per_s, pc.eff_modulus_pa, pc.eff_radius_m);
    const double f = 4.0 / 3.0 * pc.eff_modulus_pa * std::sqrt(pc.eff_radius_m) * std::pow(xi, 1.5);
    const double tc = hertz_contact_time_s(pc.reduced_mass_kg, pc.approach_speed_m_per_s, pc.eff_modulus_pa, pc.eff_radius_m);
    EXPECT_NEAR(r.max_overlap_m / xi, 1.0, tight);
    EXPECT_NEAR(r.max_normal_force_n / f, 1.0, 1.5 * tight);
    EXPECT_NEAR(r.contact_time_s / tc, 1.0, 2.0 / c.steps_per_contact);
    const double rebound = r.velocity2_m_per_s.z() - r.velocity1_m_per_s.z();
    EXPECT_NEAR(-rebound / pc.approach_speed_m_per_s, 1.0, tight);
    EXPECT_NEAR(r.energy_after_j / r.energy_before_j, 1.0, tight);
}

/// An oblique impact against the rigid-body answer: exact where the contact
/// slides throughout; where it ends sticking, only no energy created.
void expect_rigid_body(const ImpactCase& c, const ImpactResult& r, const char* what)
{
    const RigidBodyImpact rb = rigid_body_impact(c);
    const PairConstants pc = pair_constants(c);
    const Inertias k = inertias_of(c);
    EXPECT_LE(r.energy_after_j, r.energy_before_j * (1.0 + tight)) << what << ": energy created";
    const double vz_scale = pc.approach_speed_m_per_s;
    EXPECT_NEAR(r.velocity1_m_per_s.z(), rb.velocity1_m_per_s.z(), 2.0 * tight * vz_scale) << what;
    if (!rb.slides_throughout) return;
    const double friction_impulse = c.friction_coeff * (1.0 + c.restitution) * pc.reduced_mass_kg * vz_scale;
    const FiniteContactTolerance finite = finite_contact_tolerance(c);
    const double rel = spring_phase_shortfall(c, TangentialParams{}.stiffness_per_m) + finite.impulse + 2.0 * tight;
    EXPECT_NEAR(r.velocity1_m_per_s.x(), rb.velocity1_m_per_s.x(), rel * friction_impulse * k.inv_mass1) << what;
    EXPECT_NEAR(r.spin1_rad_per_s, rb.spin1_rad_per_s,
        (rel + finite.lever1) * friction_impulse * c.radius1_m * k.inv_inertia1) << what;
    if (c.target != Target::plate) {
        EXPECT_NEAR(r.velocity2_m_per_s.x(), rb.velocity2_m_per_s.x(), rel * friction_impulse * k.inv_mass2) << what;
    }
    if (c.target == Target::grain) {
        EXPECT_NEAR(r.spin2_rad_per_s, rb.spin2_rad_per_s,
            (rel + finite.lever2) * friction_impulse * c.radius2_m * k.inv_inertia2) << what;
    }
}

} // namespace

INSTANTIATE_TEST_SUITE_P(Integrators, ChungOoi, ::testing::Values(Integrator::gear5, Integrator::verlet),
    [](const ::testing::TestParamInfo<Integrator>& i) { return i.param == Integrator::gear5 ? "Gear5" : "Verlet"; });

TEST_P(ChungOoi, Test1ElasticNormalImpactOfTwoIdenticalSpheres)
{
    for (const Material& m : {glass, limestone}) {
        ImpactCase c = with_integrator({});
        c.material1 = c.material2 = m;
        c.radius1_m = c.radius2_m = 0.010;
        c.target = Target::grain;
        c.velocity1_m_per_s = Vec3(0, 0, -10.0);
        c.velocity2_m_per_s = Vec3(0, 0, 10.0);
        expect_hertz(c, run_impact(c));
    }
}

TEST_P(ChungOoi, Test2ElasticNormalImpactOfASphereWithAPlate)
{
    for (const Material& m : {aluminium_alloy, magnesium_alloy}) {
        ImpactCase c = with_integrator({});
        c.material1 = m;
        c.material2 = rigid(m);
        c.radius1_m = 0.10;
        c.velocity1_m_per_s = Vec3(0, 0, -0.2);
        expect_hertz(c, run_impact(c));
    }
}

TEST_P(ChungOoi, Test3NormalImpactWithDampingGivesTheRestitutionAsked)
{
    // γ_n is derived from e at the impact's own speed and pair (docs/model.md,
    // "γ_n from a restitution"): the engine must give e back. Its bisection
    // and RK4 reference hold e to ~10⁻⁴; the engine's step to 1e-3.
    for (const Material& m : {aluminium_oxide, cast_iron})
        for (const double e : {0.2, 0.4, 0.6, 0.8, 1.0}) {
            ImpactCase c = with_integrator({});
            c.material1 = m;
            c.material2 = rigid(m);
            c.radius1_m = 2.5e-3;
            c.velocity1_m_per_s = Vec3(0, 0, -3.9);
            c.restitution = e;
            const ImpactResult r = run_impact(c);
            EXPECT_NEAR(r.velocity1_m_per_s.z() / 3.9, e, 2.0 * tight) << "e = " << e;
        }
}

TEST_P(ChungOoi, Test4ObliqueImpactOnAPlateAtConstantSpeedOverTheImpactAngles)
{
    // 3.9 m/s at θ from the normal, μ = 0.092: the contact slides throughout
    // above tan θ = (7/2) μ (1 + e) = 0.644 (θ = 32.8°).
    for (const Material& m : {aluminium_oxide, aluminium_alloy})
        for (const double deg : {2.0, 10.0, 20.0, 30.0, 40.0, 60.0, 80.0}) {
            const double th = deg * std::numbers::pi / 180.0;
            ImpactCase c = with_integrator({});
            c.material1 = m;
            c.material2 = rigid(m);
            c.radius1_m = 2.5e-3;
            c.friction_coeff = 0.092;
            c.velocity1_m_per_s = 3.9 * Vec3(std::sin(th), 0, -std::cos(th));
            EXPECT_EQ(rigid_body_impact(c).slides_throughout, std::tan(th) >= 3.5 * 0.092 * 2.0) << deg;
            expect_rigid_body(c, run_impact(c), "Test 4");
        }
}

TEST_P(ChungOoi, Test5ObliqueImpactOnAPlateAtConstantNormalSpeed)
{
    // 5 m/s normal, tangential speeds up to 10 times it.
    for (const double vt : {0.5, 2.0, 4.0, 10.0, 25.0, 50.0}) {
        ImpactCase c = with_integrator({});
        c.material1 = aluminium_alloy;
        c.material2 = rigid(aluminium_alloy);
        c.radius1_m = 2.5e-3;
        c.friction_coeff = 0.4;
        c.velocity1_m_per_s = Vec3(vt, 0, -5.0);
        expect_rigid_body(c, run_impact(c), "Test 5");
    }
}

TEST_P(ChungOoi, Test6ImpactOnAPlateWithInitialSpin)
{
    // Head-on at 3.9 m/s with spin only: the slip is ω R; the contact slides
    // throughout above |ω| R = (7/2) μ (1 + e) v_n.
    const double r = 2.5e-3, mu = 0.092;
    for (const double spin_over_threshold : {-3.0, -0.5, 0.3, 1.5, 4.0}) {
        ImpactCase c = with_integrator({});
        c.material1 = aluminium_oxide;
        c.material2 = rigid(aluminium_oxide);
        c.radius1_m = r;
        c.friction_coeff = mu;
        c.velocity1_m_per_s = Vec3(0, 0, -3.9);
        c.spin1_rad_per_s = spin_over_threshold * 3.5 * mu * 2.0 * 3.9 / r;
        expect_rigid_body(c, run_impact(c), "Test 6");
    }
}

TEST_P(ChungOoi, Test7ObliqueImpactOfTwoIdenticalSpheres)
{
    // Equal spheres: 1/m_t = 2/m + 2 R²/I = 7/m, so sliding throughout above
    // |s₀| = μ (1 + e) (m/2) v_n · 7/m = (7/2) μ (1 + e) v_n, as on a plate.
    for (const double deg : {10.0, 30.0, 45.0, 60.0, 80.0}) {
        const double th = deg * std::numbers::pi / 180.0;
        ImpactCase c = with_integrator({});
        c.material1 = c.material2 = aluminium_oxide;
        c.radius1_m = c.radius2_m = 2.5e-3;
        c.target = Target::grain;
        c.friction_coeff = 0.092;
        c.velocity1_m_per_s = 3.9 * Vec3(std::sin(th), 0, -std::cos(th));
        expect_rigid_body(c, run_impact(c), "Test 7");
    }
}

TEST_P(ChungOoi, Test8ImpactOfSpheresOfDifferentSizesWithSpin)
{
    // A sphere of 2.5 mm onto one of 5 mm at rest, 3.9 m/s normal, with
    // spins of either sign on the smaller one, and tangential speed.
    for (const double spin : {-8000.0, -500.0, 0.0, 3000.0})
        for (const double vt : {0.0, 2.0}) {
            if (spin == 0.0 && vt == 0.0) continue;
            ImpactCase c = with_integrator({});
            c.material1 = c.material2 = aluminium_oxide;
            c.radius1_m = 2.5e-3;
            c.radius2_m = 5e-3;
            c.target = Target::grain;
            c.friction_coeff = 0.092;
            c.velocity1_m_per_s = Vec3(vt, 0, -3.9);
            c.spin1_rad_per_s = spin;
            expect_rigid_body(c, run_impact(c), "Test 8");
        }
}

TEST_P(ChungOoi, GrainOnAMembraneNodeNormalAndOblique)
{
    // The paper's grain onto a free membrane node (a point mass that does not
    // turn, with the paper's membrane material): Hertz head-on, and oblique
    // impacts with the paper's μ = 0.3, where 1/m_t = 1/m₁ + R₁²/I₁ + 1/m_node.
    ImpactCase c = with_integrator({});
    c.material1 = paper_grain;
    c.radius1_m = paper_grain_radius_m;
    c.target = Target::membrane_node;
    c.material2 = paper_membrane;
    c.radius2_m = paper_node_radius_m;
    c.node_mass_kg = paper_node_mass_kg;
    c.velocity1_m_per_s = Vec3(0, 0, -0.5);
    expect_hertz(c, run_impact(c));
    c.friction_coeff = 0.3;
    for (const double vt : {0.05, 0.5, 2.0}) {
        c.velocity1_m_per_s = Vec3(vt, 0, -0.5);
        expect_rigid_body(c, run_impact(c), "grain on a membrane node");
    }
}

TEST(ChungOoiTheory, TheRigidBodyLinesAreTheClosedForms)
{
    // The reference itself, against the textbook forms for a sphere on a
    // plate (e = 1; spin about +y rolls along +x): sliding, v_x' = v_x − 2μ v_n and
    // ω' R = 5 μ v_n; sticking,
    // v_x' = ω' R = (5/7) v_x.
    ImpactCase c;
    c.material1 = aluminium_oxide;
    c.material2 = rigid(aluminium_oxide);
    c.radius1_m = 2.5e-3;
    c.friction_coeff = 0.1;
    c.velocity1_m_per_s = Vec3(3.0, 0, -1.0);
    RigidBodyImpact rb = rigid_body_impact(c);
    const double reduced = pair_constants(c).reduced_mass_kg / sphere_mass_of(c.material1, c.radius1_m);
    EXPECT_TRUE(rb.slides_throughout);
    EXPECT_NEAR(rb.velocity1_m_per_s.x(), 3.0 - 2.0 * 0.1 * reduced, 1e-12);
    EXPECT_NEAR(rb.spin1_rad_per_s * c.radius1_m, 5.0 * 0.1 * reduced, 1e-12);
    EXPECT_NEAR(rb.velocity1_m_per_s.z(), -1.0 + 2.0 * reduced, 1e-12);
    c.velocity1_m_per_s = Vec3(0.5, 0, -1.0);
    rb = rigid_body_impact(c);
    EXPECT_FALSE(rb.slides_throughout);
    EXPECT_NEAR(rb.velocity1_m_per_s.x(), 5.0 / 7.0 * 0.5, 1e-12);
    EXPECT_NEAR(rb.spin1_rad_per_s * c.radius1_m, 5.0 / 7.0 * 0.5, 1e-12);
}
