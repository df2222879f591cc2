// Motion types (state/body_state.hpp, Motion): a kinematic body moves at its
// prescribed velocity whatever the forces, a fixed one does not move or turn,
// and both still receive (and report) the forces of their contacts. A
// kinematic body is an infinitely heavy one: a grain it strikes leaves with
// the velocity of a collision with an infinite mass, and the energy the grain
// gains is the work of the reported force along the prescribed path.
#include "helpers.hpp"
#include "integrate/flat_runs.hpp"
#include "laws/hertz.hpp"
#include "step.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

const Material grain_material{10e9, 0.3, 7800.0};
constexpr double radius_m = 1.23e-3;

double grain_mass_kg() { return sphere_mass_kg(grain_material.density_kg_per_m3, radius_m); }
double e_star_pa() { return effective_modulus_pa(10e9, 0.3, 10e9, 0.3); }

constexpr BodyRef piston{BodyKind::grain, 0};
constexpr BodyRef struck{BodyKind::grain, 1};

/// A kinematic grain (the piston) moving along +x at v into a grain at rest,
/// until they have parted.
struct Impact {
    Vec3 piston_start_m;   ///< where the piston started
    Vec3 piston_end_m;     ///< where it ended
    Vec3 piston_path_m;    ///< x₀ + x₁ + x₁ + …, added as the integrator adds it
    Vec3 piston_velocity;  ///< its velocity at the end [m/s]
    Vec3 piston_velocity_set; ///< its velocity when it was set (v, as stored: v δt / δt) [m/s]
    Vec3 struck_velocity;  ///< the struck grain's velocity at the end [m/s]
    double work_j = 0.0;   ///< Σ −F_piston · Δx_piston: the work the piston did on the grain
    std::size_t contact_steps = 0;
    bool newton_third = true; ///< the piston's reported force is minus the grain's, every step in contact
};

Impact strike(double v, double damping_s, Integrator integrator, double steps_per_contact)
{
    const double tc = hertz_contact_time_s(grain_mass_kg(), v, e_star_pa(), 0.5 * radius_m);
    Simulation sim(1);
    reset_world(sim.world, grain_material, tc / steps_per_contact, damping_s);
    World& w = sim.world;
    w.integrator = integrator;
    const double gap = 10.0 * v * w.dt_s; // touch after a few steps
    add_grain(w, Vec3(-2.0 * radius_m - gap, 0, 0), radius_m, 0);
    add_grain(w, Vec3::Zero(), radius_m, 0);
    set_motion(w, piston, Motion::kinematic);
    set_velocity(w, piston, Vec3(v, 0, 0));

    Impact r;
    r.piston_velocity_set = velocity_m_per_s(w, piston);
    r.piston_start_m = w.of(BodyKind::grain).x[0][0];
    r.piston_path_m = r.piston_start_m;
    bool started = false;
    for (int s = 0; s < 1'000'000; ++s) {
        const Vec3 step_m = w.of(BodyKind::grain).x[1][0];
        sim.step();
        r.piston_path_m += step_m;
        const Vec3 f_piston = w.force_of(BodyKind::grain)[0];
        r.work_j -= f_piston.dot(step_m);
        const bool touching = w.contacts.size() == 1 && w.contacts.touching[0];
        if (touching) {
            started = true;
            ++r.contact_steps;
            r.newton_third = r.newton_third && f_piston == -w.force_of(BodyKind::grain)[1] && f_piston.x() < 0.0;
        } else if (started) {
            break;
        }
    }
    r.piston_end_m = w.of(BodyKind::grain).x[0][0];
    r.piston_velocity = velocity_m_per_s(w, piston);
    r.struck_velocity = velocity_m_per_s(w, struck);
    return r;
}

class KinematicImpact : public ::testing::TestWithParam<Integrator> {};

} // namespace

INSTANTIATE_TEST_SUITE_P(Integrators, KinematicImpact, ::testing::Values(Integrator::gear5, Integrator::verlet),
    [](const auto& info) { return info.param == Integrator::gear5 ? std::string("Gear5") : std::string("Verlet"); });

TEST_P(KinematicImpact, PistonFollowsItsVelocityExactlyAndReportsTheContactForce)
{
    const double v = 0.5;
    const Impact r = strike(v, 0.0, GetParam(), 200.0);
    ASSERT_GT(r.contact_steps, 100u);
    // The prescribed path, bit for bit: the contact did not slow it.
    EXPECT_EQ(r.piston_end_m, r.piston_path_m);
    EXPECT_EQ(r.piston_velocity, r.piston_velocity_set);
    EXPECT_TRUE(r.newton_third);
}

TEST_P(KinematicImpact, AnElasticImpactIsACollisionWithAnInfiniteMass)
{
    // In the piston's frame the grain arrives at −v and, elastically, leaves
    // at +v: 2v in the lab. The collision tests resolve restitution to 1e-3
    // at 200 steps per contact; the same tolerance here.
    const double v = 0.5;
    const Impact r = strike(v, 0.0, GetParam(), 200.0);
    EXPECT_NEAR(r.struck_velocity.x() / (2.0 * v), 1.0, 1e-3);
    EXPECT_EQ(r.struck_velocity.y(), 0.0);
    EXPECT_EQ(r.struck_velocity.z(), 0.0);
    // No energy from nowhere: the grain's ½ m (2v)² is the work the piston's
    // reported force did along its path. The force is sampled once per step
    // (a rectangle rule over the N steps of contact), so the sum is exact to
    // O(1/N).
    const double gained_j = 0.5 * grain_mass_kg() * r.struck_velocity.squaredNorm();
    EXPECT_NEAR(r.work_j / gained_j, 1.0, 1.0 / static_cast<double>(r.contact_steps));
}

TEST_P(KinematicImpact, ADampedImpactLeavesAtOnePlusRestitutionTimesTheSpeed)
{
    // The damping that gives e for a grain against an infinite mass (reduced
    // mass m): the grain leaves at (1 + e) v, to the collision tests' 1 % of e;
    // the work of the piston exceeds the grain's energy by what the dashpot
    // took (never less: no energy from nowhere).
    const double v = 0.5;
    for (double e : {0.3, 0.7}) {
        const double gamma = hertz_damping_for_restitution_s(e, grain_mass_kg(), v, e_star_pa(), 0.5 * radius_m);
        const Impact r = strike(v, gamma, GetParam(), 200.0);
        EXPECT_NEAR(r.struck_velocity.x() - v, e * v, 0.01 * e * v) << "e = " << e;
        const double gained_j = 0.5 * grain_mass_kg() * r.struck_velocity.squaredNorm();
        EXPECT_GT(r.work_j, gained_j) << "e = " << e;
    }
}

TEST(Motion, AFixedGrainNeitherMovesNorTurnsAndFeelsTheBlow)
{
    // An oblique, frictional blow on a fixed grain: its position and
    // orientation stay bit for bit, it reports the contact's force (minus
    // the striker's), and the striker leaves with no more energy than it had.
    Simulation sim(1);
    reset_world(sim.world, grain_material, 2e-8, 1e-5);
    World& w = sim.world;
    w.contact.tangential.friction_coeff = 0.5;
    add_grain(w, Vec3::Zero(), radius_m, 0);
    add_grain(w, Vec3(-2.0 * radius_m, 0.8 * radius_m, 0), radius_m, 0, Vec3(1.0, 0, 0), Vec3(0, 0, 300.0));
    set_motion(w, {BodyKind::grain, 0}, Motion::fixed);
    const Vec3 x0 = w.of(BodyKind::grain).x[0][0];
    const Quat q0 = w.grain_rotation.orientation[0];
    const double energy_before_j = kinetic_energy_j(w, sim.pool());
    bool felt = false;
    for (int s = 0; s < 20000; ++s) {
        sim.step();
        const Vec3 f = w.force_of(BodyKind::grain)[0];
        if (w.contacts.size() == 1 && w.contacts.touching[0]) {
            felt = felt || f.norm() > 0.0;
            EXPECT_EQ(f, -w.force_of(BodyKind::grain)[1]) << "step " << s;
        }
    }
    EXPECT_TRUE(felt);
    EXPECT_EQ(w.of(BodyKind::grain).x[0][0], x0);
    EXPECT_EQ(w.grain_rotation.orientation[0].coeffs(), q0.coeffs());
    EXPECT_EQ(velocity_m_per_s(w, {BodyKind::grain, 0}), Vec3::Zero());
    EXPECT_EQ(angular_velocity_rad_per_s(w, 0), Vec3::Zero());
    EXPECT_LT(kinetic_energy_j(w, sim.pool()), energy_before_j);
}

TEST(Motion, SetMotionStopsWhatItMustAndAFreedBodyKeepsItsVelocity)
{
    World w;
    add_material(w, grain_material);
    w.dt_s = 1e-6;
    add_grain(w, Vec3::Zero(), radius_m, 0, Vec3(1, 2, 3), Vec3(4, 5, 6));
    TranslationalState& g = w.of(BodyKind::grain);
    for (int k = 2; k < gear_order; ++k) g.x[k][0] = Vec3(1e-9, 0, 0);
    const Vec3 v = velocity_m_per_s(w, {BodyKind::grain, 0});
    set_motion(w, {BodyKind::grain, 0}, Motion::kinematic);
    EXPECT_EQ(velocity_m_per_s(w, {BodyKind::grain, 0}), v);
    for (int k = 2; k < gear_order; ++k) EXPECT_EQ(g.x[k][0], Vec3::Zero()) << "x" << k;
    EXPECT_EQ(angular_velocity_rad_per_s(w, 0), Vec3::Zero());
    set_motion(w, {BodyKind::grain, 0}, Motion::dynamic);
    EXPECT_EQ(velocity_m_per_s(w, {BodyKind::grain, 0}), v);
    set_motion(w, {BodyKind::grain, 0}, Motion::fixed);
    EXPECT_EQ(velocity_m_per_s(w, {BodyKind::grain, 0}), Vec3::Zero());
    // Two bodies that are not dynamic need no contact.
    add_grain(w, Vec3(1.5 * radius_m, 0, 0), radius_m, 0);
    set_motion(w, {BodyKind::grain, 1}, Motion::kinematic);
    Simulation sim(1);
    sim.world = w;
    update_neighbours(sim.world, sim.pool());
    EXPECT_EQ(sim.world.contacts.size(), 0u);
    set_motion(sim.world, {BodyKind::grain, 1}, Motion::dynamic);
    update_neighbours(sim.world, sim.pool());
    EXPECT_EQ(sim.world.contacts.size(), 1u);
}

// The integrators find runs of one motion type eight bodies per word
// (integrate/flat_runs.hpp); against a loop body by body, for every motion at
// every place of ranges of every length and start up to three words, and for
// mixed motions drawn at random.
TEST(Motion, WordWiseRunTestsAgreeWithABodyByBodyLoop)
{
    constexpr Motion kinds[] = {Motion::dynamic, Motion::kinematic, Motion::fixed};
    std::vector<std::vector<Motion>> cases;
    for (const Motion base : kinds)
        for (const Motion odd : kinds)
            for (std::size_t at = 0; at < 26; ++at) {
                cases.emplace_back(26, base);
                cases.back()[at] = odd;
            }
    std::uint64_t state = 11;
    for (int c = 0; c < 100; ++c) {
        cases.emplace_back(26);
        for (Motion& m : cases.back()) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            m = kinds[(state >> 33) % 3];
        }
    }
    for (const std::vector<Motion>& motion : cases)
        for (std::size_t b = 0; b <= motion.size(); ++b)
            for (std::size_t e = b; e <= motion.size(); ++e)
                for (const Motion which : kinds) {
                    bool all = true, any = false;
                    for (std::size_t i = b; i < e; ++i) {
                        all = all && motion[i] == which;
                        any = any || motion[i] == which;
                    }
                    ASSERT_EQ(all_of_motion(motion, which, b, e), all) << b << " " << e;
                    ASSERT_EQ(any_of_motion(motion, which, b, e), any) << b << " " << e;
                }
}
