// The one contact pipeline (engine/step.cpp, compute_contact_forces): pair
// and wall contacts go through the same kernel and laws, and a wall's
// contacts live in the contact list with their tangential memory.
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

constexpr double radius_m = 1.23e-3;
const Material grain_material{10e9, 0.3, 7800.0};
const Material plate_material{1e9, 0.3, 7800.0};

/// Force and torque on a grain at height z above z = 0, moving with v and
/// spinning with ω, against the plate z = 0 (big_radius_m = 0) or against a
/// held sphere of the plate's material and radius big_radius_m whose top is
/// at z = 0. One force evaluation, fresh springs.
struct Evaluated {
    Vec3 force_n, torque_n_m;
};
Evaluated contact_on_grain(double z_m, const Vec3& v, const Vec3& omega, double big_radius_m)
{
    Simulation sim(1);
    World& w = sim.world;
    reset_world(w, grain_material, 1e-7);
    const std::uint8_t plate = add_material(w, plate_material);
    add_grain(w, Vec3(0, 0, z_m), radius_m, 0, v, omega);
    if (big_radius_m > 0.0) {
        const std::uint32_t big = add_grain(w, Vec3(0, 0, -big_radius_m), big_radius_m, plate);
        set_motion(w, {BodyKind::grain, big}, Motion::fixed); // held, like the plate
    } else {
        add_wall(w, make_plate(0.0, +1.0, plate));
    }
    update_neighbours(w, sim.pool());
    compute_contact_forces(w, sim.pool());
    gather_forces(w, sim.pool());
    return {w.body_force_n[0][0], w.grain_torque_n_m[0]};
}

} // namespace

TEST(ContactPipeline, ASphereOfGrowingRadiusPressesLikeAPlaneInTheLimit)
{
    // The same overlap, oblique velocity and spin against a plane and against
    // spheres of radius R = 10 r … 10⁵ r. Every force (normal, and the
    // tangential spring's, ∝ F_n) scales with √R* = √(r R/(r + R)), so the
    // sphere's force and torque are the plane's times √(R/(r + R)): within
    // the rounding of the sphere's overlap, r + R − |x − x_R| (a few ulp of
    // R, relative to ξ; 3/2 of that in F ∝ ξ^{3/2}), and → the plane's as R → ∞.
    const double overlap = 1e-3 * radius_m;
    const Vec3 v(0.05, -0.02, -0.1), omega(3.0, 1.0, -2.0);
    const Evaluated plane = contact_on_grain(radius_m - overlap, v, omega, 0.0);
    ASSERT_GT(plane.force_n.z(), 0.0);
    ASSERT_GT(std::hypot(plane.force_n.x(), plane.force_n.y()), 0.0); // friction acts
    double previous_gap = std::numeric_limits<double>::infinity();
    for (double ratio = 10.0; ratio <= 1e5; ratio *= 10.0) {
        const double big = ratio * radius_m;
        const Evaluated sphere = contact_on_grain(radius_m - overlap, v, omega, big);
        const double scale = std::sqrt(big / (radius_m + big));
        const double rounding = 1.5 * 8.0 * std::numeric_limits<double>::epsilon() * (big + radius_m) / overlap + 1e-14;
        EXPECT_LT((sphere.force_n - scale * plane.force_n).norm(), rounding * plane.force_n.norm()) << "R = " << ratio << " r";
        EXPECT_LT((sphere.torque_n_m - scale * plane.torque_n_m).norm(), rounding * plane.torque_n_m.norm())
            << "R = " << ratio << " r";
        const double gap = (sphere.force_n - plane.force_n).norm() / plane.force_n.norm();
        EXPECT_LT(gap, previous_gap) << "R = " << ratio << " r";
        EXPECT_LT(gap, radius_m / big) << "R = " << ratio << " r"; // 1 − √(R/(r+R)) ≈ r/(2R)
        previous_gap = gap;
    }
}

TEST(ContactPipeline, AnObliqueImpactOnAWallWithFrictionGainsNoEnergy)
{
    // A grain hits the floor at 1 m/s without spin, at angles from grazing to
    // steep, with an elastic normal law (γ_n = 0): friction (sticking spring
    // or Coulomb sliding) is the only way energy can change, and it may only
    // take energy. Bound: the integrator's own error, measured as the
    // energy change of the same impact without friction (μ = 0).
    auto impact = [](double angle_rad, double mu) {
        Simulation sim(1);
        World& w = sim.world;
        reset_world(w, grain_material, 1e-7);
        w.contact.tangential.friction_coeff = mu;
        const std::uint8_t plate = add_material(w, plate_material);
        add_wall(w, make_plate(0.0, +1.0, plate));
        const Vec3 v_in(std::cos(angle_rad), 0.0, -std::sin(angle_rad));
        add_grain(w, Vec3(0, 0, 1.01 * radius_m), radius_m, 0, v_in);
        set_time_step(w, stable_time_step(w, 1.0).auto_s);
        auto energy = [&] { return kinetic_energy_j(w, sim.pool()); };
        const double before = energy();
        bool touched = false;
        for (int s = 0; s < 1000000; ++s) {
            sim.step();
            touched = touched || w.wall_loads[0].contacts > 0;
            if (touched && w.wall_loads[0].contacts == 0) break;
        }
        EXPECT_TRUE(touched);
        EXPECT_EQ(w.wall_loads[0].contacts, 0u) << "the grain left the floor";
        return energy() / before;
    };
    for (double degrees : {5.0, 20.0, 45.0, 70.0, 85.0}) {
        const double angle = degrees * std::numbers::pi / 180.0;
        const double frictionless = impact(angle, 0.0);
        const double integrator_error = std::abs(frictionless - 1.0);
        EXPECT_LT(integrator_error, 1e-3) << degrees << "°"; // measured: ≤ 1.2e-4 (Gear-5, auto δt)
        const double with_friction = impact(angle, 0.3); // measured: 0.76–0.9997 of the energy kept
        EXPECT_LE(with_friction, 1.0 + integrator_error) << degrees << "°";
        EXPECT_LT(with_friction, frictionless) << degrees << "°: friction took no energy";
    }
}

TEST(ContactPipeline, WallContactMemorySurvivesRebuildsAndIsDroppedWhenTheContactOpens)
{
    // A grain held on the floor by a load, sheared sideways so that its wall
    // spring is loaded. A twin world whose neighbour list is rebuilt before
    // every step must stay bit-identical: the spring is carried across each
    // rebuild. Then the grain is pulled off: its spring must be gone while it
    // is still listed (within the skin), so a new touch starts afresh.
    auto build = [](Simulation& sim) {
        World& w = sim.world;
        reset_world(w, grain_material, 1e-7);
        const std::uint8_t plate = add_material(w, plate_material);
        add_wall(w, make_plate(0.0, +1.0, plate));
        add_grain(w, Vec3(0, 0, radius_m), radius_m, 0);
        w.grain_rotation.inv_inertia_per_kg_m2[0] = 0.0; // no rolling: the spring takes the shear
        w.point_loads.push_back({BodyRef(BodyKind::grain, 0), Vec3(0.05, 0.0, -1.0)}); // below μ F_n
        set_time_step(w, stable_time_step(w, 0.1).auto_s);
        w.contact.normal_damping_s = 1e-5;
    };
    Simulation a(1), b(1);
    build(a);
    build(b);
    const BodyRef grain(BodyKind::grain, 0);
    for (int s = 0; s < 3000; ++s) {
        invalidate_neighbours(a.world); // a rebuild before every step
        a.step();
        b.step();
    }
    EXPECT_EQ(a.world.neighbour_builds, 3000u);
    EXPECT_LE(b.world.neighbour_builds, 2u);
    const auto p = a.world.contacts.find(grain, wall_ref(0));
    ASSERT_TRUE(p.has_value());
    const TangentialState& spring = a.world.contacts.tangential[*p];
    EXPECT_TRUE(spring.sticking);
    EXPECT_GT(spring.spring_m.norm(), 0.0);
    EXPECT_EQ(a.world.bodies[0].x[0][0], b.world.bodies[0].x[0][0]);
    EXPECT_EQ(a.world.bodies[0].x[1][0], b.world.bodies[0].x[1][0]);
    EXPECT_EQ(a.world.wall_loads[0].total_force_n, b.world.wall_loads[0].total_force_n);

    // Pull it up just off the floor (within the skin: it stays listed).
    World& w = a.world;
    w.point_loads.clear();
    Vec3 off = w.bodies[0].x[0][0];
    off.z() = radius_m + 0.1 * effective_skin_m(w);
    place_body(w, grain, off);
    a.step();
    const auto q = w.contacts.find(grain, wall_ref(0));
    ASSERT_TRUE(q.has_value()) << "still a candidate";
    EXPECT_FALSE(w.contacts.touching[*q]);
    EXPECT_EQ(w.contacts.tangential[*q].spring_m, Vec3::Zero());
    EXPECT_TRUE(w.contacts.tangential[*q].sticking);
    EXPECT_EQ(w.contacts.output[*q].force_n, Vec3::Zero());
    EXPECT_EQ(w.wall_loads[0].contacts, 0u);
    EXPECT_EQ(w.wall_loads[0].total_force_n, Vec3::Zero());
}

TEST(ContactPipeline, RemovingAWallKeepsTheOthersContactsAndANewWallStartsWithNone)
{
    // A grain resting on the floor against the mould (a cylinder), sheared so
    // that its floor spring is loaded. Removing the mould and adding a lid
    // (the preparation's order) must leave the floor's contact and spring as
    // they were, and the lid, now wall 1 like the mould was, without
    // contacts until the next rebuild finds some: the mould's contacts must
    // not pass for the lid's. (They did, and the preparation's lid stopped
    // where it started: Campaign.Tiny.)
    Simulation sim(1);
    World& w = sim.world;
    reset_world(w, grain_material, 1e-7);
    const std::uint8_t plate = add_material(w, plate_material);
    add_wall(w, make_plate(0.0, +1.0, plate));
    const std::size_t mould = add_wall(w, make_cylinder(10.0 * radius_m, plate));
    add_grain(w, Vec3(9.0 * radius_m + 1e-3 * radius_m, 0, radius_m - 1e-3 * radius_m), radius_m, 0, Vec3(0, 0.01, 0));
    set_time_step(w, stable_time_step(w, 0.1).auto_s);
    for (int s = 0; s < 10; ++s) sim.step();
    const BodyRef grain(BodyKind::grain, 0);
    ASSERT_TRUE(w.contacts.wall_touches(0, BodyKind::grain));
    ASSERT_TRUE(w.contacts.wall_touches(mould, BodyKind::grain));
    const auto floor_before = w.contacts.find(grain, wall_ref(0));
    ASSERT_TRUE(floor_before.has_value());
    const TangentialState spring = w.contacts.tangential[*floor_before];
    ASSERT_GT(spring.spring_m.norm(), 0.0);

    remove_wall(w, mould);
    const std::size_t lid = add_wall(w, make_plate(10.0 * radius_m, -1.0, plate));
    ASSERT_EQ(lid, mould);
    EXPECT_FALSE(w.contacts.wall_touches(lid, BodyKind::grain));
    EXPECT_FALSE(w.contacts.find(grain, wall_ref(static_cast<std::uint32_t>(lid))).has_value());
    const auto floor_after = w.contacts.find(grain, wall_ref(0));
    ASSERT_TRUE(floor_after.has_value());
    EXPECT_EQ(w.contacts.tangential[*floor_after].spring_m, spring.spring_m);
    EXPECT_TRUE(w.contacts.touching[*floor_after]);
    sim.step();
    EXPECT_TRUE(w.contacts.wall_touches(0, BodyKind::grain));
    EXPECT_FALSE(w.contacts.wall_touches(lid, BodyKind::grain)); // the lid is far above
}

TEST(ContactPipeline, AListHoldsForTheSkinItWasBuiltWithWhateverTheSkinIsSetToSince)
{
    // One grain flies head-on at a held one, 1.5 skins s apart, and the list
    // is built with s (the pair is not in it). Then skin_m is raised to 4 s,
    // with no rebuild. The list holds only until something has moved s/2:
    // the pair must be listed before they touch, and the impact is Hertz's,
    // δ_max = (15 m v² / (16 E* √R*))^(2/5) (no damping). Checked against
    // the new skin (2 s of travel) the grain would be 0.5 s deep before any
    // contact force.
    Simulation sim(1);
    World& w = sim.world;
    reset_world(w, grain_material, 1e-8);
    const double s = 0.1 * radius_m, v = 1.0;
    w.skin_m = s;
    add_grain(w, Vec3::Zero(), radius_m, 0);
    set_motion(w, {BodyKind::grain, 0}, Motion::fixed);
    add_grain(w, Vec3(2.0 * radius_m + 1.5 * s, 0, 0), radius_m, 0, Vec3(-v, 0, 0));
    sim.step();
    ASSERT_EQ(w.neighbour_builds, 1u);
    ASSERT_EQ(w.contacts.pair_count(), 0u) << "1.5 skins apart: not listed";
    w.skin_m = 4.0 * s;

    const double m = w.of(BodyKind::grain).mass_kg[1];
    const double e_star = effective_modulus_pa(grain_material.youngs_modulus_pa, grain_material.poisson_ratio,
        grain_material.youngs_modulus_pa, grain_material.poisson_ratio);
    const double r_star = effective_radius_m(radius_m, radius_m);
    const double hertz_m = std::pow(15.0 * m * v * v / (16.0 * e_star * std::sqrt(r_star)), 0.4);
    double deepest = 0.0;
    const auto& x = w.of(BodyKind::grain).x[0];
    while (w.of(BodyKind::grain).x[1][1].x() < 0.0) { // until it bounces back
        sim.step();
        deepest = std::max(deepest, 2.0 * radius_m - (x[1] - x[0]).norm());
        ASSERT_GT(x[1].x(), radius_m) << "it passed into the held grain";
    }
    EXPECT_GE(w.neighbour_builds, 2u);
    // The discrete impact's peak to the integrator's error (10⁴ steps per contact).
    EXPECT_NEAR(deepest / hertz_m, 1.0, 1e-2);
}
