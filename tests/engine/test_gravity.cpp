// A sphere on the bottom plate under gravity: static overlap, sticking,
// sliding and rolling on an incline (gravity tilted by θ).
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

constexpr double radius_m = 1.23e-3;
constexpr double g = 10.0;
const Material grain_material{10e9, 0.3, 7800.0};
const Material plate_material{1e9, 0.3, 7800.0};

/// A sphere resting on the plate z = 0, settled with strong normal damping so
/// that it starts at its static overlap. `lock_rotation` gives it infinite inertia.
struct Resting {
    Simulation sim{1};
    double mass_kg = sphere_mass_kg(grain_material.density_kg_per_m3, radius_m);
    double e_star_pa = effective_modulus_pa(10e9, 0.3, 1e9, 0.3);

    explicit Resting(bool lock_rotation)
    {
        World& w = sim.world;
        w.gravity_m_per_s2 = Vec3(0, 0, -g);
        add_material(w, grain_material);
        add_material(w, plate_material);
        add_wall(w, make_plate(0.0, +1.0, 1));
        add_grain(w, Vec3(0, 0, radius_m), radius_m, 0);
        if (lock_rotation) w.grain_rotation.inv_inertia_per_kg_m2[0] = 0.0;
        w.dt_s = stable_time_step(w).auto_s;
        const double tc = hertz_contact_time_s(mass_kg, 0.01, e_star_pa, radius_m);
        w.contact.normal_damping_s = hertz_damping_for_restitution_s(0.1, mass_kg, 0.01, e_star_pa, radius_m);
        sim.run(static_cast<std::uint64_t>(200 * tc / w.dt_s));
    }
    [[nodiscard]] double overlap_m() const { return radius_m - sim.world.bodies[0].x[0][0].z(); }
    [[nodiscard]] Vec3 velocity() const { return velocity_m_per_s(sim.world, {BodyKind::grain, 0}); }
    [[nodiscard]] double spin_y() const { return angular_velocity_rad_per_s(sim.world, 0).y(); }

    /// Tilts gravity by θ about y: the plate becomes an incline going down along +x.
    void tilt(double theta)
    {
        sim.world.gravity_m_per_s2 = g * Vec3(std::sin(theta), 0, -std::cos(theta));
    }

    /// Least-squares slope of a sampled quantity over `duration_s`, after a lead-in.
    template <class F>
    double slope(F quantity, double lead_in_s, double duration_s)
    {
        const double dt = sim.world.dt_s;
        sim.run(static_cast<std::uint64_t>(lead_in_s / dt));
        double st = 0, sq = 0, stt = 0, stq = 0;
        const int samples = 400;
        const auto every = static_cast<std::uint64_t>(duration_s / dt / samples);
        for (int k = 0; k < samples; ++k) {
            sim.run(every);
            const double t = k * every * dt, q = quantity();
            st += t; sq += q; stt += t * t; stq += t * q;
        }
        return (samples * stq - st * sq) / (samples * stt - st * st);
    }
};

} // namespace

TEST(SphereOnPlate, StaticOverlapMatchesHertz)
{
    Resting r(false);
    // m g = (4/3) E* √R ξ^{3/2}  ⇒  ξ = (3 m g / (4 E* √R))^{2/3}
    const double expected = std::pow(3 * r.mass_kg * g / (4 * r.e_star_pa * std::sqrt(radius_m)), 2.0 / 3.0);
    EXPECT_NEAR(r.overlap_m() / expected, 1.0, 1e-3);
    EXPECT_NEAR(r.sim.world.wall_loads[0].total_force_n.z(), -r.mass_kg * g, 1e-3 * r.mass_kg * g);
}

TEST(SphereOnIncline, SticksWhileTanThetaBelowFriction)
{
    Resting r(true);
    const double mu = r.sim.world.contact.tangential.friction_coeff;
    const double k_t = r.sim.world.contact.tangential.stiffness_per_m;
    const double theta = std::atan(0.4 * mu);
    r.tilt(theta);
    const double x0 = r.sim.world.bodies[0].x[0][0].x();
    double max_shift = 0.0;
    for (int k = 0; k < 200; ++k) { // 0.1 s
        r.sim.run(static_cast<std::uint64_t>(5e-4 / r.sim.world.dt_s));
        max_shift = std::max(max_shift, std::abs(r.sim.world.bodies[0].x[0][0].x() - x0));
    }
    // The static spring holds m g sinθ at δ = tanθ / k_t; suddenly loaded it
    // oscillates up to twice that, and never slips.
    EXPECT_LE(max_shift, 2.0 * std::tan(theta) / k_t * 1.01);
    const ContactList& c = r.sim.world.contacts;
    EXPECT_TRUE(c.tangential[c.find({BodyKind::grain, 0}, wall_ref(0)).value()].sticking);
}

TEST(SphereOnIncline, SlidesWithCoulombAccelerationWhenTanThetaAboveFriction)
{
    Resting r(true);
    const double mu = r.sim.world.contact.tangential.friction_coeff;
    const double theta = std::atan(2.0 * mu);
    r.tilt(theta);
    const double a = r.slope([&] { return r.velocity().x(); }, 0.01, 0.05);
    EXPECT_NEAR(a / (g * (std::sin(theta) - mu * std::cos(theta))), 1.0, 0.01);
}

TEST(SphereOnIncline, RollsWithoutSlipBelowThreeAndAHalfTimesFriction)
{
    Resting r(false);
    const double mu = r.sim.world.contact.tangential.friction_coeff;
    const double theta = std::atan(mu);
    r.tilt(theta);
    // Rolling solid sphere: a = (5/7) g sinθ, and v = ω r at the contact.
    const double a = r.slope([&] { return r.velocity().x(); }, 0.01, 0.1);
    EXPECT_NEAR(a / (5.0 / 7.0 * g * std::sin(theta)), 1.0, 0.01);
    EXPECT_NEAR(r.spin_y() * (radius_m - r.overlap_m()) / r.velocity().x(), 1.0, 0.01);
}

TEST(SphereOnIncline, SlidesAndSpinsUpAboveThreeAndAHalfTimesFriction)
{
    Resting r(false);
    const double mu = r.sim.world.contact.tangential.friction_coeff;
    const double theta = std::atan(5.0 * mu);
    r.tilt(theta);
    const double a = r.slope([&] { return r.velocity().x(); }, 0.01, 0.05);
    EXPECT_NEAR(a / (g * (std::sin(theta) - mu * std::cos(theta))), 1.0, 0.01);
    // Friction μ m g cosθ at lever r: α = 5 μ g cosθ / (2 r).
    const double alpha = r.slope([&] { return r.spin_y(); }, 0.0, 0.05);
    EXPECT_NEAR(alpha / (5.0 * mu * g * std::cos(theta) / (2.0 * radius_m)), 1.0, 0.01);
}
