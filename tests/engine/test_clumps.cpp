// Rigid multi-sphere grains (clumps; state/clump_shape.hpp,
// state/clump_state.hpp, integrate/clumps.hpp): the mass properties of a
// union of spheres against closed forms (a lone sphere, two touching
// spheres, a dumbbell, two overlapping spheres); torque-free rotation of an
// asymmetric clump keeps its energy and angular momentum over many turns and
// is unstable about the intermediate axis only, in both integrators; a clump
// dropped on a plate comes to rest on a face; spheres of one clump never
// touch; the same bits on any number of threads; a snapshot continues
// bit-identically.
#include "helpers.hpp"
#include "integrate/clumps.hpp"
#include "io/snapshot.hpp"
#include "laws/hertz.hpp"
#include "laws/rolling.hpp"
#include "state/state_hash.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <unistd.h>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

constexpr double pi = std::numbers::pi;

/// ∫_a^b Σ c_k u^k du.
double poly_integral(const std::vector<double>& c, double a, double b)
{
    double s = 0.0;
    for (std::size_t k = 0; k < c.size(); ++k)
        s += c[k] * (std::pow(b, static_cast<double>(k + 1)) - std::pow(a, static_cast<double>(k + 1))) / (k + 1.0);
    return s;
}

/// Product of two polynomials (coefficients by ascending power).
std::vector<double> times(const std::vector<double>& a, const std::vector<double>& b)
{
    std::vector<double> c(a.size() + b.size() - 1, 0.0);
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < b.size(); ++j) c[i + j] += a[i] * b[j];
    return c;
}

/// The closed form of two equal spheres of radius R whose centres are d ≤ 2R
/// apart along z: a solid of revolution with ρ²(z) = R² − (|z| − d/2)².
/// Returns (V, I_zz, I_xx) per unit density about the centre.
Vec3 overlapping_pair(double big_r, double d)
{
    const double h = 0.5 * d;
    const std::vector<double> rho2{big_r * big_r, 0.0, -1.0}; // R² − u², u = |z| − h ∈ [−h, R]
    const std::vector<double> z2{h * h, 2.0 * h, 1.0};          // (u + h)²
    const double volume = 2.0 * pi * poly_integral(rho2, -h, big_r);
    const double rho4 = poly_integral(times(rho2, rho2), -h, big_r);
    const double i_zz = pi * rho4;                                            // 2 · ∫ π ρ⁴/2
    const double i_xx = 0.5 * pi * rho4 + 2.0 * pi * poly_integral(times(z2, rho2), -h, big_r); // 2 · ∫ (π ρ⁴/4 + z² π ρ²)
    return {volume, i_zz, i_xx};
}

double sphere_volume(double r)
{
    return 4.0 / 3.0 * pi * r * r * r;
}

/// A World without gravity holding one clump of `shape` (scaled to a largest
/// sphere of 1 mm, ρ = 2600) turning at ω (space frame), δt such that
/// |ω| δt = `turn_per_step`.
void spinning_clump(World& w, const std::string& shape, const Vec3& omega, Integrator integrator, double turn_per_step)
{
    reset_world(w, Material{1e8, 0.3, 2600.0}, turn_per_step / omega.norm());
    set_integrator(w, integrator);
    const ClumpBody body = scaled_clump(clump_body(*builtin_clump_template(shape)), 1e-3);
    add_clump(w, body, Vec3::Zero(), Quat::Identity(), 0, Vec3::Zero(), omega);
}

double rotational_energy_j(const World& w)
{
    return clump_kinetic_energy_j(w);
}

} // namespace

TEST(ClumpMassProperties, ALoneSphereIsExact)
{
    const UnionMassProperties p = union_mass_properties({{Vec3(0.3, -0.2, 0.1), 0.7}});
    EXPECT_NEAR(p.volume_m3 / sphere_volume(0.7), 1.0, 1e-13);
    EXPECT_NEAR((p.centre_m - Vec3(0.3, -0.2, 0.1)).norm(), 0.0, 1e-13);
    const double i = 0.4 * sphere_volume(0.7) * 0.49; // 2/5 V r²
    EXPECT_NEAR((p.inertia_m5 - i * Eigen::Matrix3d::Identity()).norm() / i, 0.0, 1e-12);
}

TEST(ClumpMassProperties, TwoEqualTouchingSpheresAreTwoSpheresByTheParallelAxisTheorem)
{
    // Centres 2R apart along a slanted axis: no overlap, so each sphere counts whole.
    const double r = 1.0;
    const Vec3 axis = Vec3(1.0, 2.0, 2.0).normalized();
    const ClumpBody body = clump_body({{-r * axis, r}, {r * axis, r}});
    const double v1 = sphere_volume(r);
    EXPECT_NEAR(body.volume_m3 / (2.0 * v1), 1.0, 1e-12);
    EXPECT_NEAR(body.template_centre_m.norm(), 0.0, 1e-12);
    const double along = 2.0 * 0.4 * v1 * r * r;                  // about the line of centres
    const double across = 2.0 * (0.4 * v1 * r * r + v1 * r * r);  // + V d², d = R from the centre
    EXPECT_NEAR(body.principal_inertia_m5[0] / along, 1.0, 1e-12);
    EXPECT_NEAR(body.principal_inertia_m5[1] / across, 1.0, 1e-12);
    EXPECT_NEAR(body.principal_inertia_m5[2] / across, 1.0, 1e-12);
    // The smallest moment's axis is the line of centres; the spheres sit on body axis 1.
    EXPECT_NEAR(std::abs(body.template_axes.col(0).dot(axis)), 1.0, 1e-12);
    EXPECT_NEAR(std::abs(body.spheres[0].centre_m.x()), r, 1e-12);
    EXPECT_NEAR(body.spheres[0].centre_m.tail<2>().norm(), 0.0, 1e-12);
    EXPECT_NEAR(body.template_axes.determinant(), 1.0, 1e-12);
}

TEST(ClumpMassProperties, ADumbbellOfUnequalSpheresHasItsCentreAndMomentsInClosedForm)
{
    // Spheres of radius 1 and 0.5 with centres 3 apart (a gap of 1.5).
    const double r1 = 1.0, r2 = 0.5, d = 3.0;
    const ClumpBody body = clump_body({{Vec3(0, 0, 0), r1}, {Vec3(0, d, 0), r2}});
    const double v1 = sphere_volume(r1), v2 = sphere_volume(r2), v = v1 + v2;
    const double y_centre = v2 * d / v; // centre of mass from the big sphere
    EXPECT_NEAR(body.volume_m3 / v, 1.0, 1e-12);
    EXPECT_NEAR((body.template_centre_m - Vec3(0, y_centre, 0)).norm(), 0.0, 1e-12);
    const double along = 0.4 * (v1 * r1 * r1 + v2 * r2 * r2);
    const double across = along + v1 * y_centre * y_centre + v2 * (d - y_centre) * (d - y_centre);
    EXPECT_NEAR(body.principal_inertia_m5[0] / along, 1.0, 1e-12);
    EXPECT_NEAR(body.principal_inertia_m5[1] / across, 1.0, 1e-12);
    EXPECT_NEAR(body.principal_inertia_m5[2] / across, 1.0, 1e-12);
}

TEST(ClumpMassProperties, TwoOverlappingSpheresMatchTheClosedFormToTheStatedAccuracy)
{
    // The union of two equal spheres, centres d apart, against the solid of
    // revolution: the polar axis and the splits of cos θ follow the pair, so
    // the quadrature is Gauss-accurate (the stated 2·10⁻¹⁰ at the default n).
    const double r = 1.0;
    for (const double d : {0.4, 1.0, 1.6}) {
        const Vec3 exact = overlapping_pair(r, d);
        const ClumpBody body = clump_body({{Vec3(0, 0, -0.5 * d), r}, {Vec3(0, 0, 0.5 * d), r}});
        EXPECT_NEAR(body.volume_m3 / exact[0], 1.0, 2e-10) << "d = " << d;
        EXPECT_NEAR(body.principal_inertia_m5[0] / exact[1], 1.0, 2e-10) << "d = " << d;
        EXPECT_NEAR(body.principal_inertia_m5[1] / exact[2], 1.0, 2e-10) << "d = " << d;
        EXPECT_NEAR(body.principal_inertia_m5[2] / exact[2], 1.0, 2e-10) << "d = " << d;
        EXPECT_NEAR(body.template_centre_m.norm(), 0.0, 2e-10) << "d = " << d;
    }
}

TEST(ClumpMassProperties, BuiltInTemplatesConvergeToTheStatedAccuracy)
{
    // Three or more overlapping spheres have no closed form: the default
    // against twice the nodes, within the 2·10⁻⁶ the header states.
    for (const std::string_view name : builtin_clump_names) {
        const auto spheres = *builtin_clump_template(name);
        const ClumpBody fine = clump_body(spheres, 2 * clump_default_angular_nodes);
        const ClumpBody body = clump_body(spheres);
        EXPECT_NEAR(body.volume_m3 / fine.volume_m3, 1.0, 2e-6) << name;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(body.principal_inertia_m5[k] / fine.principal_inertia_m5[k], 1.0, 2e-6) << name;
    }
}

TEST(ClumpMassProperties, BuiltInTemplatesAreInTheirPrincipalFrames)
{
    for (const std::string_view name : builtin_clump_names) {
        const auto spheres = builtin_clump_template(name);
        ASSERT_TRUE(spheres.has_value()) << name;
        const ClumpBody body = clump_body(*spheres);
        // Recomputed in the body frame (another set of rays: the same to the
        // quadrature's accuracy): centre at the origin, the tensor diagonal.
        const UnionMassProperties again = union_mass_properties(body.spheres);
        EXPECT_NEAR(again.centre_m.norm(), 0.0, 1e-5) << name;
        const Eigen::Matrix3d off = again.inertia_m5 - Eigen::Matrix3d(again.inertia_m5.diagonal().asDiagonal());
        EXPECT_LT(off.norm(), 1e-5 * again.inertia_m5.norm()) << name;
        EXPECT_LE(body.principal_inertia_m5[0], body.principal_inertia_m5[1]) << name;
        EXPECT_LE(body.principal_inertia_m5[1], body.principal_inertia_m5[2]) << name;
    }
    // The crushed grain is asymmetric: three distinct moments.
    const ClumpBody crushed = clump_body(*builtin_clump_template("crushed"));
    EXPECT_GT(crushed.principal_inertia_m5[1] / crushed.principal_inertia_m5[0], 1.05);
    EXPECT_GT(crushed.principal_inertia_m5[2] / crushed.principal_inertia_m5[1], 1.05);
    EXPECT_FALSE(builtin_clump_template("round").has_value());
}

TEST(ClumpMassProperties, ScalingMultipliesVolumeByF3AndMomentsByF5)
{
    const auto spheres = *builtin_clump_template("crushed");
    std::vector<ClumpSphere> small_spheres = spheres;
    for (ClumpSphere& s : small_spheres) s = {1e-3 * s.centre_m, 1e-3 * s.radius_m};
    const ClumpBody small = scaled_clump(clump_body(spheres), 1e-3);
    const ClumpBody direct = clump_body(small_spheres);
    EXPECT_NEAR(small.volume_m3 / direct.volume_m3, 1.0, 1e-12);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(small.principal_inertia_m5[k] / direct.principal_inertia_m5[k], 1.0, 1e-12);
    for (std::size_t i = 0; i < spheres.size(); ++i)
        EXPECT_NEAR((small.spheres[i].centre_m - direct.spheres[i].centre_m).norm(), 0.0, 1e-15);
}

namespace {

struct FreeRotation {
    double energy_drift = 0.0;    ///< largest |E − E₀|/E₀
    double momentum_drift = 0.0;  ///< largest |L − L₀|/|L₀|
    double turns = 0.0;
};

/// Spins a crushed clump about a generic axis without torque for `steps`.
FreeRotation free_rotation(Integrator integrator, std::uint64_t steps, double turn_per_step)
{
    Simulation sim(1);
    World& w = sim.world;
    const Vec3 omega = 20.0 * Vec3(0.3, 1.0, -0.6).normalized();
    spinning_clump(w, "crushed", omega, integrator, turn_per_step);
    const double e0 = rotational_energy_j(w);
    const Vec3 l0 = clump_angular_momentum(w, 0);
    FreeRotation r;
    for (std::uint64_t s = 0; s < steps; ++s) {
        sim.step();
        r.energy_drift = std::max(r.energy_drift, std::abs(rotational_energy_j(w) / e0 - 1.0));
        r.momentum_drift = std::max(r.momentum_drift, (clump_angular_momentum(w, 0) - l0).norm() / l0.norm());
    }
    r.turns = static_cast<double>(steps) * turn_per_step / (2.0 * pi);
    // The centre stays put (no force) and no two spheres of it are in contact.
    EXPECT_EQ(w.clumps.x[0][0], Vec3::Zero());
    EXPECT_EQ(w.contacts.size(), 0u);
    return r;
}

} // namespace

TEST(ClumpRotation, TorqueFreeAsymmetricClumpKeepsEnergyAndAngularMomentumGear5)
{
    // ω δt = 0.01: 100 turns in 62 832 steps.
    const FreeRotation r = free_rotation(Integrator::gear5, 62832, 0.01);
    std::printf("Gear-5, %.0f turns at ω δt = 0.01: |ΔE|/E ≤ %.2e, |ΔL|/|L| ≤ %.2e\n", r.turns, r.energy_drift,
        r.momentum_drift);
    // Measured 2.9·10⁻⁷ and 3.8·10⁻⁷, falling as δt² (7.3·10⁻⁸, 9.4·10⁻⁸ at
    // ω δt = 0.005): the corrector's velocity-dependent gyroscopic term.
    EXPECT_LT(r.energy_drift, 1e-6);
    EXPECT_LT(r.momentum_drift, 1e-6);
}

TEST(ClumpRotation, TorqueFreeAsymmetricClumpKeepsEnergyAndAngularMomentumVerlet)
{
    const FreeRotation r = free_rotation(Integrator::verlet, 62832, 0.01);
    std::printf("Verlet, %.0f turns at ω δt = 0.01: |ΔE|/E ≤ %.2e, |ΔL|/|L| ≤ %.2e\n", r.turns, r.energy_drift,
        r.momentum_drift);
    EXPECT_LT(r.energy_drift, 1e-4);   // bounded oscillation of a symplectic splitting, O((ω δt)²)
    EXPECT_LT(r.momentum_drift, 1e-12); // each part of the splitting keeps L exactly
}

namespace {

/// Spins the crushed clump about body axis k (0, 1, 2) with a perturbation
/// of 10⁻⁶ of ω on the other two; returns the smallest ω_k/ω_k(0) over
/// `duration` seconds.
double spin_axis_component_min(Integrator integrator, int k, double duration_s)
{
    Simulation sim(1);
    World& w = sim.world;
    Vec3 omega_body = Vec3::Constant(1e-6 * 20.0);
    omega_body[k] = 20.0;
    reset_world(w, Material{1e8, 0.3, 2600.0}, 0.005 / 20.0);
    set_integrator(w, integrator);
    const ClumpBody body = scaled_clump(clump_body(*builtin_clump_template("crushed")), 1e-3);
    add_clump(w, body, Vec3::Zero(), Quat::Identity(), 0, Vec3::Zero(), omega_body); // identity: body = space
    double smallest = 1.0;
    const auto steps = static_cast<std::uint64_t>(duration_s / w.dt_s);
    for (std::uint64_t s = 0; s < steps; ++s) {
        sim.step();
        smallest = std::min(smallest, w.clumps.omega[1][0][k] / w.dt_s / 20.0);
    }
    return smallest;
}

} // namespace

TEST(ClumpRotation, SpinAboutTheIntermediateAxisIsUnstableAndAboutTheOthersStable)
{
    // Linearised Euler equations about ω₂: perturbations grow as e^{λt},
    // λ = ω √((I₂ − I₁)(I₃ − I₂)/(I₁ I₃)); from 10⁻⁶ the spin flips after
    // about ln(10⁶)/λ. Over three times that, spin about axis 2 reverses
    // (ω₂ < 0: the Dzhanibekov flip), about axes 1 and 3 it stays within
    // 10⁻³ of what it was.
    const Vec3 i = clump_body(*builtin_clump_template("crushed")).principal_inertia_m5;
    const double lambda = 20.0 * std::sqrt((i[1] - i[0]) * (i[2] - i[1]) / (i[0] * i[2]));
    const double duration = 3.0 * std::log(1e6) / lambda;
    for (const Integrator integrator : {Integrator::gear5, Integrator::verlet}) {
        const char* name = integrator == Integrator::gear5 ? "gear5" : "verlet";
        EXPECT_LT(spin_axis_component_min(integrator, 1, duration), -0.5) << name;
        EXPECT_GT(spin_axis_component_min(integrator, 0, duration), 1.0 - 1e-3) << name;
        EXPECT_GT(spin_axis_component_min(integrator, 2, duration), 1.0 - 1e-3) << name;
    }
}

namespace {

/// A flat clump (four spheres of 2 mm in a square) dropped tilted onto a
/// plate under gravity: E = 10⁸ Pa, ρ = 2600, restitution 0.3, μ = 0.3.
void flat_clump_over_plate(World& w, Integrator integrator, const Quat& tilt)
{
    reset_world(w, Material{1e8, 0.3, 2600.0}, 1e-6);
    w.gravity_m_per_s2 = Vec3(0, 0, -10.0);
    set_integrator(w, integrator);
    add_wall(w, make_plate(0.0, +1.0, 0));
    const ClumpBody body = scaled_clump(clump_body(*builtin_clump_template("flat")), 2e-3);
    const double mass = 2600.0 * body.volume_m3;
    const double e_star = effective_modulus_pa(1e8, 0.3, 1e8, 0.3);
    w.contact.normal_damping_s = hertz_damping_for_restitution_s(0.3, mass / 4.0, 0.3, e_star, 2e-3);
    add_clump(w, body, Vec3(0, 0, 8e-3), tilt, 0, Vec3(0.02, 0, -0.1), Vec3(0, 0, 3.0));
    set_time_step(w, stable_time_step(w).auto_s);
}

} // namespace

TEST(ClumpOnPlate, AFlatClumpDroppedTiltedComesToRestOnItsFace)
{
    // Dropped 6 mm (4 mm of free fall to the lowest sphere), tilted by 0.5 rad
    // and spinning, it bounces, rocks and settles flat. A sticking contact's
    // tangential spring has no dashpot (the model spec §3), so the clump's
    // sway and twist on its four springs ring down only through the normal
    // damping: after 0.3 s its kinetic energy is ~10⁻⁶ of the drop's
    // (measured 10⁻¹¹–10⁻¹² J against 1.9·10⁻⁵ J) and stays there. Since
    // the step counts the tangential springs (8.17 µs here; docs/model.md,
    // "The tangential and rolling springs in the step") Verlet, which does
    // not damp them numerically, keeps them ringing at 10⁻¹¹–2·10⁻¹⁰ J
    // from 0.3 to 0.9 s, not growing (Gear-5 4·10⁻¹⁴–10⁻¹¹ J). The bound is
    // what the sticking springs can hold: a spring of stiffness k_t F_n
    // sticks up to μ F_n, so stores at most μ² F_n / (2 k_t), and the four
    // carry the weight, Σ F_n = m g: a ringing that stays within the springs
    // has E_k ≤ μ² m g / (2 k_t) (4.5·10⁻⁶ m J here, 7.5·10⁻⁵ of the drop).
    for (const Integrator integrator : {Integrator::gear5, Integrator::verlet}) {
        Simulation sim(1);
        World& w = sim.world;
        flat_clump_over_plate(w, integrator, Quat(Eigen::AngleAxisd(0.5, Vec3(1, 1, 0).normalized())));
        const double mass = w.clumps.mass_kg[0];
        const double drop_j = mass * 10.0 * (8e-3 - 2e-3);
        const char* name = integrator == Integrator::gear5 ? "gear5" : "verlet";
        ASSERT_EQ(sim.run(static_cast<std::uint64_t>(0.3 / w.dt_s)).end, RunEnd::completed) << name;
        double largest_j = 0.0, largest_tilt = 0.0;
        for (int ms = 0; ms < 100; ++ms) {
            ASSERT_EQ(sim.run(static_cast<std::uint64_t>(1e-3 / w.dt_s)).end, RunEnd::completed) << name;
            largest_j = std::max(largest_j, kinetic_energy_j(w, sim.pool()));
            const Vec3 normal = w.clumps.orientation[0] * Vec3::UnitZ(); // body axis 3: normal to the square
            largest_tilt = std::max(largest_tilt, std::acos(std::min(1.0, std::abs(normal.z()))));
            EXPECT_EQ(w.wall_loads[0].contacts, 4u) << name << " at " << 300 + ms << " ms";
        }
        std::printf("%s: from 0.3 to 0.4 s, E_k ≤ %.2g J (%.2g of the drop), tilt ≤ %.2g°, centre at %.4f mm\n", name,
            largest_j, largest_j / drop_j, largest_tilt * 180.0 / pi, 1e3 * w.clumps.x[0][0].z());
        const double mu = w.contact.tangential.friction_coeff;
        const double springs_hold_j = mu * mu * mass * 10.0 / (2.0 * w.contact.tangential.stiffness_per_m);
        EXPECT_LT(largest_j, springs_hold_j) << name;
        // On its face: the axis of the largest moment vertical, all four
        // spheres on the plate, the centre one sphere radius up.
        EXPECT_LT(largest_tilt, 0.5 * pi / 180.0) << name;
        EXPECT_NEAR(w.clumps.x[0][0].z(), 2e-3, 0.05e-3) << name;
        // The plate carries the weight.
        EXPECT_NEAR(w.wall_loads[0].total_force_n.z(), -mass * 10.0, 1e-2 * mass * 10.0) << name;
    }
}

namespace {

struct OnIncline {
    double slip_m = 0.0;         ///< the centre's travel along the slope over the hold
    double acceleration = 0.0;   ///< along the slope over the hold's second half [m/s²]
    double tilt_rad = 0.0;       ///< how far its face turned from the plate
};

/// The flat clump (spheres of 2 mm on a square of side 3 mm) resting on its
/// face, then gravity tilted to β over 20 ms (a sudden tilt overshoots: a
/// sticking spring has no dashpot) and held for `time_s` (the plate stays z = 0).
OnIncline flat_clump_on_incline(double tan_beta, double friction, double time_s)
{
    Simulation sim(1);
    World& w = sim.world;
    flat_clump_over_plate(w, Integrator::gear5, Quat::Identity());
    w.contact.tangential.friction_coeff = friction;
    // Down onto the plate and to rest on its face, under vertical gravity.
    w.clumps.x[0][0] = Vec3(0, 0, 2e-3);
    w.clumps.x[1][0] = Vec3::Zero();
    w.clumps.omega[1][0] = Vec3::Zero();
    place_clump_spheres(w, 0, w.clumps.orientation[0]);
    invalidate_prediction(w);
    invalidate_neighbours(w);
    relax(sim, static_cast<std::uint64_t>(0.05 / w.dt_s), 0.002);
    const double beta = std::atan(tan_beta);
    const auto per_ms = static_cast<std::uint64_t>(1e-3 / w.dt_s);
    for (int ms = 1; ms <= 20; ++ms) {
        const double b = beta * ms / 20.0;
        w.gravity_m_per_s2 = 10.0 * Vec3(std::sin(b), 0, -std::cos(b));
        EXPECT_EQ(sim.run(per_ms).end, RunEnd::completed);
    }
    const Vec3 start = w.clumps.x[0][0];
    const auto half = static_cast<std::uint64_t>(0.5 * time_s / w.dt_s);
    EXPECT_EQ(sim.run(half).end, RunEnd::completed);
    const double v1 = w.clumps.x[1][0].x() / w.dt_s;
    EXPECT_EQ(sim.run(half).end, RunEnd::completed);
    OnIncline r;
    r.slip_m = w.clumps.x[0][0].x() - start.x();
    r.acceleration = (w.clumps.x[1][0].x() / w.dt_s - v1) / (static_cast<double>(half) * w.dt_s);
    r.tilt_rad = std::acos(std::min(1.0, (w.clumps.orientation[0] * Vec3::UnitZ()).z()));
    return r;
}

} // namespace

TEST(ClumpOnIncline, HoldsSlidesOrTipsWhereStaticsSays)
{
    // Statics of the flat clump on a plate tilted by β: it slides once
    // tan β > μ, and tips over its downhill spheres once its centre of mass
    // (one sphere radius r up) passes over their contact points (0.75 r
    // downhill of it): tan β > 0.75.
    // μ = 0.3, tan β = 0.2: holds.
    const OnIncline holds = flat_clump_on_incline(0.2, 0.3, 0.05);
    EXPECT_LT(std::abs(holds.slip_m), 1e-6);
    EXPECT_LT(holds.tilt_rad, 1e-3);
    // μ = 0.3, tan β = 0.45: slides without tipping, at g (sin β − μ cos β).
    const double beta = std::atan(0.45);
    const double a = 10.0 * (std::sin(beta) - 0.3 * std::cos(beta));
    const OnIncline slides = flat_clump_on_incline(0.45, 0.3, 0.05);
    std::printf("sliding: %.4g m/s² against g (sin β − μ cos β) = %.4g m/s²\n", slides.acceleration, a);
    EXPECT_NEAR(slides.acceleration, a, 0.02 * a);
    EXPECT_LT(slides.tilt_rad, 0.02);
    // μ = 1: tan β = 0.65 holds; tan β = 0.85 tips.
    const OnIncline stands = flat_clump_on_incline(0.65, 1.0, 0.05);
    EXPECT_LT(std::abs(stands.slip_m), 1e-6);
    EXPECT_LT(stands.tilt_rad, 1e-3);
    const OnIncline tips = flat_clump_on_incline(0.85, 1.0, 0.1);
    std::printf("tan β = 0.85, μ = 1: turned %.1f° in 0.1 s\n", tips.tilt_rad * 180.0 / pi);
    EXPECT_GT(tips.tilt_rad, 0.5);
}

namespace {

/// Clumps of every built-in shape (or of `only_shape` alone) and free grains
/// falling into a cylinder and kicked: contacts between clumps, with grains,
/// with both walls.
void build_clump_column(World& w, Integrator integrator, std::string_view only_shape = {})
{
    reset_world(w, Material{1e8, 0.3, 2600.0}, 1e-6);
    w.gravity_m_per_s2 = Vec3(0, 0, -10.0);
    set_integrator(w, integrator);
    add_wall(w, make_plate(0.0, +1.0, 0));
    add_wall(w, make_cylinder(4e-3, 0));
    SplitMix64 rng(11);
    int placed = 0;
    double lightest = 1.0;
    for (int layer = 0; layer < 6; ++layer)
        for (int a = -1; a <= 1; ++a)
            for (int b = -1; b <= 1; ++b) {
                const Vec3 at(2.3e-3 * a, 2.3e-3 * b, 1.3e-3 + 2.3e-3 * layer);
                if (at.head<2>().norm() > 2.5e-3) continue;
                const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
                // Towards the middle of the bottom (they meet within a few ms), and a random part.
                const Vec3 kick = -0.5 * Vec3(at.x(), at.y(), at.z()).normalized()
                                + 0.2 * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
                if (++placed % 4 == 0) {
                    add_grain(w, at, 0.7e-3, 0, kick);
                    continue;
                }
                const std::string_view shape
                    = only_shape.empty() ? builtin_clump_names[static_cast<std::size_t>(placed) % 4] : only_shape;
                const ClumpBody body = scaled_clump(clump_body(*builtin_clump_template(shape), 24), 0.5e-3);
                add_clump(w, body, at, uniform_orientation(u1, u2, u3), 0, kick, Vec3(300.0 * u1, -200.0, 100.0));
                lightest = std::min(lightest, w.clumps.mass_kg.back());
            }
    // Restitution 0.3 at 0.3 m/s for the lightest clumps head-on.
    w.contact.normal_damping_s = hertz_damping_for_restitution_s(
        0.3, 0.5 * lightest, 0.3, effective_modulus_pa(1e8, 0.3, 1e8, 0.3), 0.25e-3);
    set_time_step(w, stable_time_step(w).auto_s);
}

/// Touching contacts between two clumps' spheres (asserting none within a
/// clump), and bodies touching walls.
std::pair<std::size_t, std::size_t> clump_contacts(const World& w)
{
    std::size_t between = 0;
    for (std::size_t p = 0; p < w.contacts.size(); ++p) {
        const BodyRef a = w.contacts.first[p], b = w.contacts.second[p];
        if (is_wall(b) || a.kind() != BodyKind::grain || b.kind() != BodyKind::grain) continue;
        if (!w.clumps.is_member(a.index()) || !w.clumps.is_member(b.index())) continue;
        EXPECT_NE(w.clumps.member_clump[a.index()], w.clumps.member_clump[b.index()]);
        between += w.contacts.touching[p] != 0;
    }
    std::size_t walls = 0;
    for (const WallLoad& l : w.wall_loads) walls += l.contacts;
    return {between, walls};
}

std::vector<std::uint64_t> run_clump_column(unsigned threads, Integrator integrator)
{
    Simulation sim(threads);
    build_clump_column(sim.world, integrator);
    std::vector<std::uint64_t> hashes;
    std::size_t between = 0, walls = 0; // contact-steps
    for (int block = 0; block < 8; ++block) {
        for (int s = 0; s < 1000; ++s) {
            EXPECT_FALSE(sim.step().blew_up);
            const auto [b, wl] = clump_contacts(sim.world);
            between += b;
            walls += wl;
        }
        hashes.push_back(state_hash(sim.world));
    }
    // Clumps touched each other and the walls, over many steps.
    EXPECT_GT(between, 1000u);
    EXPECT_GT(walls, 1000u);
    if (threads == 1)
        std::printf("δt = %.3g s: %zu contact-steps between clumps' spheres, %zu with walls\n", sim.world.dt_s, between, walls);
    return hashes;
}

} // namespace

TEST(ClumpColumn, SameBitsOnOneAndSeveralThreads)
{
    for (const Integrator integrator : {Integrator::gear5, Integrator::verlet}) {
        const std::vector<std::uint64_t> reference = run_clump_column(1, integrator);
        EXPECT_EQ(run_clump_column(2, integrator), reference);
        EXPECT_EQ(run_clump_column(3, integrator), reference);
    }
}

TEST(ClumpColumn, SameBitsWithTheSimdPathsAsWithTheScalarCode)
{
    // The clumps' turns, Verlet's free rotation and the spheres' placement
    // run in SIMD lanes (integrate/clump_simd.cpp), several clumps at a
    // time where neighbouring clumps have as many spheres, the scalar code
    // for the others: the columns of one shape run mostly in lanes, the
    // mixed one mostly not. Each must give the scalar code's bits.
    const RestoreSimdKernels restore;
    const std::vector<SimdKernels> choices = simd_choices();
    if (choices.empty()) GTEST_SKIP() << "this CPU runs no SIMD path";
    for (const Integrator integrator : {Integrator::gear5, Integrator::verlet})
        for (const std::string_view shape : {std::string_view{}, std::string_view{"tetrahedral"}, std::string_view{"crushed"}}) {
            const auto hashes = [&](SimdKernels kernels) {
                set_simd_kernels(kernels);
                Simulation sim(2);
                build_clump_column(sim.world, integrator, shape);
                std::vector<std::uint64_t> h;
                for (int block = 0; block < 3; ++block) {
                    EXPECT_EQ(sim.run(1000).end, RunEnd::completed);
                    h.push_back(state_hash(sim.world));
                }
                return h;
            };
            const std::vector<std::uint64_t> scalar = hashes(SimdKernels::scalar);
            for (const SimdKernels kernels : choices)
                EXPECT_EQ(hashes(kernels), scalar) << "integrator " << static_cast<int>(integrator) << ", shape '"
                                                   << shape << "', SIMD choice " << static_cast<int>(kernels);
        }
}

TEST(ClumpColumn, RollingResistanceActsOnClumpsSpheresWithTheSameBitsOnAnyThreads)
{
    // The rolling law (laws/rolling.hpp) between clumps' spheres and on the
    // walls: its torques appear, the column runs, and the bits do not depend
    // on the thread count.
    std::vector<std::uint64_t> hashes;
    for (const unsigned threads : {1u, 3u}) {
        Simulation sim(threads);
        build_clump_column(sim.world, Integrator::gear5);
        sim.world.contact.rolling = RollingParams{0.1, 1.0, 0.3};
        std::size_t rolling = 0;
        for (int s = 0; s < 4000; ++s) {
            ASSERT_FALSE(sim.step().blew_up);
            const World& w = sim.world;
            for (std::size_t p = 0; p < w.contacts.size(); ++p)
                rolling += w.contacts.first[p].kind() == BodyKind::grain && w.clumps.is_member(w.contacts.first[p].index())
                        && w.contacts.rolling_torque_n_m[p].norm() > 0.0;
        }
        EXPECT_GT(rolling, 1000u) << "contact-steps of clumps' spheres with a rolling torque";
        hashes.push_back(state_hash(sim.world));
    }
    EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(ClumpColumn, ASnapshotContinuesBitIdentically)
{
    for (const Integrator integrator : {Integrator::gear5, Integrator::verlet}) {
        Simulation original(2);
        build_clump_column(original.world, integrator);
        ASSERT_EQ(original.run(2500).end, RunEnd::completed); // the clumps have met
        const std::filesystem::path path
            = std::filesystem::temp_directory_path() / ("wiredem_test_clumps_" + std::to_string(::getpid()) + ".h5");
        const auto saved = save_snapshot(original.world, path);
        ASSERT_TRUE(saved.ok()) << saved.error();
        auto restored = restore_snapshot(path);
        std::filesystem::remove(path);
        ASSERT_TRUE(restored.ok()) << restored.error();
        Simulation resumed(1);
        resumed.world = std::move(restored).value();
        ASSERT_EQ(resumed.world.clumps.size(), original.world.clumps.size());
        for (int block = 0; block < 3; ++block) {
            ASSERT_EQ(original.run(300).end, RunEnd::completed);
            ASSERT_EQ(resumed.run(300).end, RunEnd::completed);
            ASSERT_EQ(state_hash(resumed.world), state_hash(original.world)) << "after " << (block + 1) * 300 << " steps";
        }
    }
}

TEST(ClumpColumn, TheStableTimeStepTakesTheSmallestSphereAndTheLightestMassAContactSees)
{
    // The time step's Hertz limit takes, per kind, the smallest radius and
    // the lightest mass: for a clump, its smallest sphere and the smallest
    // effective mass at a sphere, 1/(1/M + |b|²/I₁) (M for a sphere at the
    // centre of mass), never the spheres' own (zero) masses.
    World w;
    reset_world(w, Material{1e8, 0.3, 2600.0}, 1e-6);
    add_wall(w, make_plate(0.0, +1.0, 0));
    ClumpBody body = scaled_clump(clump_body(*builtin_clump_template("crushed")), 1e-3);
    body.spheres.back().radius_m *= 0.25; // one small sphere (the mass properties kept)
    add_clump(w, body, Vec3(0, 0, 5e-3), Quat::Identity(), 0);
    const double m = w.clumps.mass_kg[0], i1 = w.clumps.principal_inertia_kg_m2[0].minCoeff();
    double lightest = m, smallest = 1.0;
    for (const ClumpSphere& s : body.spheres) {
        lightest = std::min(lightest, 1.0 / (1.0 / m + s.centre_m.squaredNorm() / i1));
        smallest = std::min(smallest, s.radius_m);
    }
    const StabilityInputs in = stability_inputs(w);
    const auto grain = static_cast<std::size_t>(BodyKind::grain);
    EXPECT_DOUBLE_EQ(in.kinds[grain].min_radius_m, smallest);
    EXPECT_DOUBLE_EQ(in.kinds[grain].min_mass_kg, lightest);
    EXPECT_LT(lightest, m);
    const double step = stable_time_step(w).critical_s;
    EXPECT_GT(step, 0.0);
    EXPECT_TRUE(std::isfinite(step));
}

TEST(ClumpOnPlate, RollingDampingBeyondGear5sDampedBoundStaysBoundedByItsLimit)
{
    // The rolling dashpot of a clump's sphere takes I_r = I₁ + M (|b| + r)²,
    // several times the clump's own I₁, and k_r ∝ F_n: pressed by 10⁴ g, the
    // crushed clump's Σ C_r δt/I₁ over its contacts reaches ~1.5, far beyond
    // the c δt/m ≈ 0.16 at which Gear-5 diverges on a linear dashpot
    // (gear5_damping_limit). It stays bounded: the law clips the torque to
    // μ_r R* F_n and has no dashpot at full mobilisation, so an oscillation
    // of the dashpot saturates. Measured: E_k over the last 90 % of 10⁵ steps
    // ≤ 1.4·10⁻⁵ J with η_r = 0.3, 4.6·10⁻⁵ J with η_r = 0, against
    // 1.9·10⁻³ J of weight × 1 mm (docs/model.md, "A calibrated gravel": the
    // gravel blow-up was a pressed Hertz contact, not this). At the springs'
    // packing step (0.61 of the old one) the ringing is chaotic in δt: 0.9–25
    // ·10⁻⁵ J at 0.8–1.15 times the auto step (2.0·10⁻⁵ J at it), against the
    // 1.9·10⁻³ J the fall releases (the centre 1.03 mm lower at rest). So the
    // bound is half of what the fall released: a bounded ringing stays under
    // it, a diverging one passes it. (Not bounded here: the impact itself, at
    // 17 m/s far beyond ξ_ref's force, comes out with more kinetic energy
    // than the fall released when rolling resistance is on — by 2.8·10⁻⁴ J
    // with η_r = 0 and 5.5·10⁻⁴ J with η_r = 0.3 at the auto step; none
    // without it, and none at half the step: the rolling springs' step is
    // taken at ξ_ref's force, docs/model.md.)
    Simulation sim(1);
    World& w = sim.world;
    reset_world(w, Material{1e8, 0.3, 2600.0}, 1e-6);
    const double g = 1e5;
    w.gravity_m_per_s2 = Vec3(0, 0, -g);
    set_integrator(w, Integrator::gear5);
    add_wall(w, make_plate(0.0, +1.0, 0));
    const ClumpBody body = scaled_clump(clump_body(*builtin_clump_template("crushed")), 1e-3);
    const double mass = 2600.0 * body.volume_m3;
    const double e_star = effective_modulus_pa(1e8, 0.3, 1e8, 0.3);
    w.contact.normal_damping_s = hertz_damping_for_restitution_s(0.3, mass / 4.0, 0.3, e_star, 1e-3);
    w.contact.rolling = RollingParams{0.4, 1.0, 0.3};
    add_clump(w, body, Vec3(0, 0, 2.0e-3), Quat(Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized())), 0, Vec3::Zero(),
        Vec3::Zero());
    set_time_step(w, stable_time_step(w).auto_s);
    const double i1 = w.clumps.principal_inertia_kg_m2[0].minCoeff();
    const double z0 = w.clumps.x[0][0].z();
    double largest_j = 0.0, largest_cdt = 0.0;
    for (int k = 0; k < 2000; ++k) {
        ASSERT_EQ(sim.run(50).end, RunEnd::completed) << "after " << 50 * k << " steps";
        if (k >= 200) largest_j = std::max(largest_j, kinetic_energy_j(w, sim.pool()));
        double sum_c = 0.0; // Σ C_r over the clump's touching contacts, as the law takes it
        for (std::size_t p = 0; p < w.contacts.size(); ++p) {
            if (!w.contacts.touching[p]) continue;
            const std::uint32_t i = w.contacts.first[p].index();
            const double r = w.of(BodyKind::grain).radius_m[i];
            const double arm = w.clumps.member_offset_m[i].norm() + r;
            const double k_r = w.contact.tangential.stiffness_per_m * w.contacts.output[p].normal_force_n * r * r;
            sum_c += 2.0 * w.contact.rolling.damping_ratio * std::sqrt((i1 + w.clumps.mass_kg[0] * arm * arm) * k_r);
        }
        largest_cdt = std::max(largest_cdt, sum_c * w.dt_s / i1);
    }
    EXPECT_GT(largest_cdt, 1.0) << "the dashpot alone would be beyond Gear-5's bound";
    // What the fall released, M g (z₀ − z), bounds the ringing at rest.
    const double released_j = w.clumps.mass_kg[0] * g * (z0 - w.clumps.x[0][0].z());
    EXPECT_GT(released_j, 0.5 * mass * g * 1e-3);
    EXPECT_LT(largest_j, 0.5 * released_j);
    EXPECT_GT(w.wall_loads[0].contacts, 0u);
}
