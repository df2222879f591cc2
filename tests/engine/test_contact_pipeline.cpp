// The one contact pipeline (engine/step.cpp, compute_contact_forces): pair
// and wall contacts go through the same kernel and laws, and a wall's
// contacts live in the contact list with their tangential memory.
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "scene.hpp"
#include "step.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

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
        w.point_loads.set(BodyRef(BodyKind::grain, 0), Vec3(0.05, 0.0, -1.0)); // below μ F_n
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

// The near pairs (NearPairs): the kernel evaluates the listed pairs whose gap
// was below the near skin at the last selection, the gather sums only their
// records, and leaving the others out changes no bit.
namespace {

/// The kicked column nudged gently (0.05 of the kick), gravity `gravity`:
/// pairs come near, touch and part, so the near pairs are selected again
/// and again, slowly enough that the list lives near_min_list_life_steps and
/// more (else every listed pair is near).
void build_nudged_column(Simulation& sim, const Vec3& gravity)
{
    test::build_kicked_column(sim.world, 11, 5, 0.05);
    sim.world.gravity_m_per_s2 = gravity;
}

/// The gap r_a + r_b − |x_b − x_a| of listed pair p, negated: > 0 apart.
double pair_gap_m(const World& w, std::size_t p)
{
    const BodyRef a = w.contacts.first[p], b = w.contacts.second[p];
    const TranslationalState &A = w.of(a.kind()), &B = w.of(b.kind());
    return (B.x[0][b.index()] - A.x[0][a.index()]).norm() - A.radius_m[a.index()] - B.radius_m[b.index()];
}

} // namespace

TEST(NearPairs, EveryListedPairLeftOutIsApartWithItsSlotsZero)
{
    Simulation sim(1);
    build_nudged_column(sim, Vec3(0, 0, -9.81));
    World& w = sim.world;
    std::size_t left_out = 0;
    const std::uint64_t selections0 = w.near.selections;
    std::size_t selected_steps = 0;
    for (int s = 0; s < 3000; ++s) {
        ASSERT_EQ(sim.run(1).end, RunEnd::completed);
        const ContactList& c = w.contacts;
        ASSERT_EQ(w.near.for_build, w.neighbour_builds);
        selected_steps += !w.near.all;
        std::vector<bool> is_near(c.pair_count(), false);
        for (std::uint32_t p : w.near.pairs) is_near[p] = true;
        for (std::size_t p = 0; p < c.pair_count(); ++p) {
            if (is_near[p]) continue;
            ++left_out;
            // At least 0.2 near skins when the kernel ran; the corrector
            // has moved the bodies by far less since.
            ASSERT_GT(pair_gap_m(w, p), 0.1 * w.near.skin_m) << "pair " << p << " at step " << s;
            ASSERT_EQ(c.touching[p], 0) << "pair " << p;
            ASSERT_TRUE(c.tangential[p].spring_m.isZero(0.0) && c.tangential[p].sticking);
            ASSERT_TRUE(c.output[p].force_n.isZero(0.0) && c.output[p].normal_x_tangential_n.isZero(0.0)
                        && c.output[p].overlap_m == 0.0 && c.output[p].normal_force_n == 0.0);
        }
    }
    // Not vacuous: pairs were left out, selections came while the column moved.
    EXPECT_GT(left_out, 10000u);
    EXPECT_GT(w.near.selections - selections0, 10u);
    EXPECT_GT(w.neighbour_builds, 2u);
    EXPECT_GT(selected_steps, 2000u);
}

TEST(NearPairs, APairThatTouchedAndIsFarAtTheSelectionIsReleased)
{
    // Two grains pressed together, evaluated; then one is moved (by hand,
    // between calls of the stages) 0.3 skins away: less than half the skin,
    // so the list stays, but more than the near skin, so the selection
    // leaves the pair out, and must release it as the kernel would.
    Simulation sim(1);
    World& w = sim.world;
    reset_world(w, grain_material, 1e-7);
    add_grain(w, Vec3(0, 0, 0), radius_m, 0);
    add_grain(w, Vec3(1.99 * radius_m, 0, 0), radius_m, 0, Vec3(0.01, 0.02, 0));
    update_neighbours(w, sim.pool());
    compute_contact_forces(w, sim.pool());
    ASSERT_EQ(w.contacts.size(), 1u);
    ASSERT_EQ(w.contacts.touching[0], 1);
    ASSERT_FALSE(w.contacts.tangential[0].spring_m.isZero(0.0));
    w.bodies[0].x[0][1].x() += 0.31 * w.skin_at_build_m;
    const std::uint64_t selections = w.near.selections;
    EXPECT_FALSE(update_neighbours(w, sim.pool()));
    EXPECT_EQ(w.near.selections, selections + 1);
    ASSERT_EQ(w.contacts.size(), 1u);
    EXPECT_TRUE(w.near.pairs.empty());
    EXPECT_EQ(w.contacts.touching[0], 0);
    EXPECT_TRUE(w.contacts.tangential[0].spring_m.isZero(0.0) && w.contacts.tangential[0].sticking);
    EXPECT_TRUE(w.contacts.output[0].force_n.isZero(0.0) && w.contacts.output[0].normal_force_n == 0.0);
    compute_contact_forces(w, sim.pool());
    gather_forces(w, sim.pool());
    EXPECT_TRUE(w.body_force_n[0][0].isZero(0.0) && w.body_force_n[0][1].isZero(0.0));
}

TEST(NearPairs, TheGatherGivesTheBitsOfASumOverEveryListedContact)
{
    // Gravity with a −0 component too: the force starts from +0 there.
    for (const Vec3& gravity : {Vec3(0, 0, -9.81), Vec3(-0.0, 0.0, -9.81)}) {
        Simulation sim(1);
        build_nudged_column(sim, gravity);
        World& w = sim.world;
        std::size_t compared = 0;
        for (int s = 0; s < 600; ++s) {
            ASSERT_EQ(sim.run(1).end, RunEnd::completed);
            if (s % 50 != 49) continue;
            // The scalar gather's sum over every listed contact of each grain.
            const ContactList& c = w.contacts;
            const TranslationalState& g = w.of(BodyKind::grain);
            const Vec3 weight_per_kg = w.gravity_m_per_s2 + Vec3::Zero();
            for (std::size_t i = 0; i < g.size(); ++i) {
                Vec3 f = g.mass_kg[i] * weight_per_kg;
                Vec3 tau = Vec3::Zero();
                for (std::uint32_t e = c.incidence_start[i]; e < c.incidence_start[i + 1]; ++e) {
                    const ContactOutput& out = c.output[c.incidence[e].contact()];
                    f += c.incidence[e].sign() * out.force_n;
                    tau += (g.radius_m[i] - 0.5 * out.overlap_m) * out.normal_x_tangential_n;
                }
                ASSERT_EQ(std::memcmp(f.data(), w.body_force_n[0][i].data(), sizeof f), 0) << "grain " << i;
                ASSERT_EQ(std::memcmp(tau.data(), w.grain_torque_n_m[i].data(), sizeof tau), 0) << "grain " << i;
                ++compared;
            }
            EXPECT_LT(w.near.pairs.size(), c.pair_count()); // some records were left out
        }
        EXPECT_GT(compared, 0u);
    }
}

TEST(NearPairs, TheListIsRebuiltAtHalfItsSkinAndTheNearPairsSelectedAtTheirLimit)
{
    // Bodies moved by hand between calls of update_neighbours (no step).
    Simulation sim(1);
    World& w = sim.world;
    reset_world(w, grain_material, 1e-7);
    for (int i = 0; i < 4; ++i) add_grain(w, Vec3(2.5 * radius_m * i, 0, 0), radius_m, 0);
    ASSERT_TRUE(update_neighbours(w, sim.pool()));
    const double skin = w.skin_at_build_m;
    ASSERT_DOUBLE_EQ(w.near.skin_m, near_skin_fraction * skin);
    const double near_limit = near_reselect_fraction * w.near.skin_m; // 0.1 skin
    std::vector<Vec3>& x = w.bodies[0].x[0];
    const std::vector<Vec3> built = x;
    auto place = [&](int body, double from_build) { x[body] = built[body] + Vec3(0, from_build * skin, 0); };
    auto update = [&](bool rebuilt, bool selected) {
        const std::uint64_t builds = w.neighbour_builds, selections = w.near.selections;
        EXPECT_EQ(update_neighbours(w, sim.pool()), rebuilt);
        EXPECT_EQ(w.neighbour_builds - builds, rebuilt ? 1u : 0u);
        EXPECT_EQ(w.near.selections - selections, selected ? 1u : 0u);
    };
    const double n = near_limit / skin;
    place(0, 0.9 * n);
    update(false, false);
    place(0, 1.1 * n); // selected again: body 0 has drifted 0.11 skins from the build
    update(false, true);
    // Body 0 on, one selection per near limit, until its drift leaves less
    // than a near limit below 0.45 skins: from then on both tests run.
    for (double at = 2.2 * n; at < 0.45; at += 1.1 * n) {
        place(0, at);
        update(false, true);
    }
    place(1, 0.5 * n); // another body, below its near limit: nothing
    update(false, false);
    place(0, 0.49);    // below half the skin from the build, less than the near limit since the selection
    update(false, false);
    place(0, 0.51);    // half the skin: rebuilt
    // That list lived no step (the last one was built at the same step
    // count): every pair of this one is near, with no selection and no near
    // test.
    update(true, false);
    EXPECT_TRUE(w.near.all);
    EXPECT_EQ(w.near.pairs.size(), w.contacts.pair_count());
    const std::vector<Vec3> rebuilt = x;
    x[2] = rebuilt[2] + Vec3(0, 1.1 * near_limit, 0);
    update(false, false);
    // A list that lived long enough: this one's pairs are selected again.
    w.step_count += near_min_list_life_steps;
    x[2] = rebuilt[2] + Vec3(0, 0.51 * skin, 0);
    update(true, true);
    EXPECT_FALSE(w.near.all);
    EXPECT_EQ(w.near.position_m.size(), w.body_count());
}
