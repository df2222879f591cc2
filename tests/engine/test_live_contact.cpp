// The stiffest live contact (engine/timestep.hpp, live_contact_limit): the
// tangent stiffness of a Hertz contact at the overlap it has now, against the
// law and against stable_time_step at the same overlap.
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "step.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

const Material grain_material{1e8, 0.3, 7800.0};
constexpr double r_a = 1.23e-3, r_b = 0.9e-3;

/// Two grains of radii r_a and `radius_b_m` on the x axis, `overlap_m` into
/// each other, at rest; their forces evaluated.
void pressed_pair(Simulation& sim, double overlap_m, double damping_s = 0.0, double radius_b_m = r_b)
{
    reset_world(sim.world, grain_material, 1e-7, damping_s);
    add_grain(sim.world, Vec3(0.0, 0.0, 0.0), r_a, 0);
    add_grain(sim.world, Vec3(r_a + radius_b_m - overlap_m, 0.0, 0.0), radius_b_m, 0);
    begin_run(sim.world, sim.pool());
}

} // namespace

TEST(LiveContactLimit, APressedHertzPairHasTheStiffnessOfTheLaw)
{
    const double e_star = effective_modulus_pa(grain_material.youngs_modulus_pa, grain_material.poisson_ratio,
        grain_material.youngs_modulus_pa, grain_material.poisson_ratio);
    const double r_star = effective_radius_m(r_a, r_b);
    for (const double fraction : {0.005, 0.02, 0.1, 0.3}) {
        const double overlap = fraction * r_star;
        Simulation sim(1);
        pressed_pair(sim, overlap);
        const LiveContactLimit live = live_contact_limit(sim.world);
        // The formula: dF/dξ = 2 E* √(R* ξ).
        const double k = hertz_stiffness_n_per_m(overlap, e_star, r_star);
        EXPECT_NEAR(live.stiffness_n_per_m, k, 1e-12 * k) << fraction;
        EXPECT_NEAR(live.overlap_m, overlap, 1e-15) << fraction;
        EXPECT_NEAR(live.reference_overlap_m, reference_overlap_fraction * r_star, 1e-18);
        EXPECT_EQ(live.kinds, "grain–grain");
        // The engine's own force: its slope between ξ ∓ h is k to O((h/ξ)²) (F ∝ ξ^{3/2}:
        // the central difference's relative error is (3/2)(1/2)(−1/2)/6 · (h/ξ)² ≈ 0.06 (h/ξ)²).
        const double h = 1e-3 * overlap;
        const auto force_at = [&](double xi) {
            Simulation s(1);
            pressed_pair(s, xi);
            return s.world.contacts.output[0].normal_force_n;
        };
        const double slope = (force_at(overlap + h) - force_at(overlap - h)) / (2.0 * h);
        EXPECT_NEAR(slope, k, 1e-6 * k) << fraction;
        // The step it allows is the undamped bound over ω = √(k/m), m the lighter grain.
        const double m = sim.world.of(BodyKind::grain).mass_kg[1];
        EXPECT_NEAR(live.mass_kg, m, 1e-15 * m);
        EXPECT_NEAR(live.critical_s, gear5_stability_limit / std::sqrt(k / m), 1e-12 * live.critical_s);
    }
}

TEST(LiveContactLimit, AtTheReferenceOverlapItIsTheStableStepsContactLimit)
{
    // Two equal grains (stable_time_step takes R* from the smallest radii)
    // pressed to ξ_ref: the live limit is stable_time_step's (the same
    // stiffness, mass and damped bound), with damping or without; 16 times as
    // deep, twice the ω (k ∝ √ξ, ω ∝ ξ^{1/4}) and so half the step
    // (undamped) or, where damping binds (ζ = ω γ_n / 3 doubles too), a
    // quarter.
    for (const double damping_s : {0.0, 2e-5, 2e-4}) {
        Simulation sim(1);
        const double r_star = effective_radius_m(r_a, r_a);
        pressed_pair(sim, reference_overlap_fraction * r_star, damping_s, r_a);
        // The normal contact alone: without friction no tangential spring
        // enters the step (its springs bind it otherwise: docs/model.md,
        // "The tangential and rolling springs in the step").
        sim.world.contact.tangential.friction_coeff = 0.0;
        const StableStep stable = stable_time_step(sim.world);
        ASSERT_EQ(stable.springs_critical_s, std::numeric_limits<double>::infinity());
        const LiveContactLimit at_reference = live_contact_limit(sim.world);
        EXPECT_NEAR(at_reference.critical_s, stable.critical_s, 1e-12 * stable.critical_s) << damping_s;

        pressed_pair(sim, 16.0 * reference_overlap_fraction * r_star, damping_s, r_a);
        const LiveContactLimit deeper = live_contact_limit(sim.world);
        const double omega = gear5_stability_limit / stable.undamped_critical_s;
        const double zeta_deeper = 2.0 * omega * damping_s / 3.0; // ω twice (16^{1/4})
        const double expected = damped_stability_limit(Integrator::gear5, zeta_deeper) / (2.0 * omega);
        EXPECT_NEAR(deeper.critical_s, expected, 1e-12 * expected) << damping_s;
        if (damping_s == 0.0) {
            EXPECT_NEAR(deeper.critical_s, 0.5 * stable.critical_s, 1e-12 * stable.critical_s);
        }
        if (damping_s == 2e-4) { // ζ ≈ 1.2 at ξ_ref: the damped bound binds at both overlaps
            EXPECT_NEAR(deeper.critical_s, 0.25 * stable.critical_s, 1e-12 * stable.critical_s);
        }
    }
}

TEST(LiveContactLimit, ContactsApartOrBetweenHeldBodiesDoNotCount)
{
    Simulation sim(1);
    pressed_pair(sim, -1e-5); // apart
    EXPECT_TRUE(std::isinf(live_contact_limit(sim.world).critical_s));
    pressed_pair(sim, 1e-5);
    set_motion(sim.world, {BodyKind::grain, 0}, Motion::kinematic);
    set_motion(sim.world, {BodyKind::grain, 1}, Motion::kinematic);
    EXPECT_TRUE(std::isinf(live_contact_limit(sim.world).critical_s));
    // One held: the other's mass alone.
    set_motion(sim.world, {BodyKind::grain, 1}, Motion::dynamic);
    EXPECT_EQ(live_contact_limit(sim.world).mass_kg, sim.world.of(BodyKind::grain).mass_kg[1]);
}

TEST(LiveContactLimit, TheSameContactOnAnyThreadCount)
{
    // A chain of 3000 grains along x (2999 contacts, three reduction blocks
    // of the list), each pair pressed a little differently, the deepest near
    // the chain's end: every thread count finds it, with the same bits.
    constexpr int grains = 3000;
    constexpr int deepest = 2500;
    const auto overlap_of = [](int i) { return i == deepest ? 4e-6 : 1e-6 * (1.0 + (i * 7919 % 1000) / 1000.0); };
    std::vector<LiveContactLimit> found;
    for (const unsigned threads : {1u, 2u, 3u}) {
        Simulation sim(threads);
        reset_world(sim.world, grain_material, 1e-7, 0.0);
        double x = 0.0;
        for (int i = 0; i < grains; ++i) {
            add_grain(sim.world, Vec3(x, 0.0, 0.0), r_a, 0);
            x += 2.0 * r_a - overlap_of(i);
        }
        begin_run(sim.world, sim.pool());
        ASSERT_GT(sim.world.contacts.size(), 2 * reduction_block);
        found.push_back(live_contact_limit(sim.world, sim.pool()));
        found.push_back(live_contact_limit(sim.world)); // on the caller alone
        EXPECT_NEAR(found.back().overlap_m, overlap_of(deepest), 1e-12) << threads;
    }
    for (const LiveContactLimit& live : found) {
        EXPECT_EQ(live.critical_s, found[0].critical_s);
        EXPECT_EQ(live.overlap_m, found[0].overlap_m);
        EXPECT_EQ(live.mass_kg, found[0].mass_kg);
        EXPECT_EQ(live.kinds, found[0].kinds);
    }
}
