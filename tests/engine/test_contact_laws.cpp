// The pure force laws against their formulas.
#include "laws/hertz.hpp"
#include "laws/tangential.hpp"

#include <gtest/gtest.h>

using namespace wiredem::engine;

TEST(HertzNormalForce, ScalesAsOverlapToThreeHalvesWithoutDamping)
{
    const double f1 = hertz_normal_force_n(1e-6, 0.0, 5e9, 6e-4, 0.0);
    const double f4 = hertz_normal_force_n(4e-6, 0.0, 5e9, 6e-4, 0.0);
    EXPECT_NEAR(f4 / f1, 8.0, 1e-12); // 4^{3/2}
    EXPECT_NEAR(f1, 4.0 / 3.0 * 5e9 * std::sqrt(6e-4) * 1e-9, 1e-12 * f1);
}

TEST(HertzNormalForce, NeverAttractsWhileSeparating)
{
    // Fast separation: ξ + γ ξ̇ < 0 would pull; the law clamps to zero.
    EXPECT_EQ(hertz_normal_force_n(1e-6, -1.0, 5e9, 6e-4, 1e-5), 0.0);
    EXPECT_GT(hertz_normal_force_n(1e-6, +1.0, 5e9, 6e-4, 1e-5), hertz_normal_force_n(1e-6, 0.0, 5e9, 6e-4, 1e-5));
}

TEST(HertzMaterial, EffectiveValuesOfIdenticalSpheresAndOfAWall)
{
    EXPECT_DOUBLE_EQ(effective_modulus_pa(10e9, 0.3, 10e9, 0.3), 10e9 / (2 * (1 - 0.09)));
    EXPECT_DOUBLE_EQ(effective_radius_m(2e-3, 2e-3), 1e-3);
    EXPECT_DOUBLE_EQ(effective_radius_m(2e-3, std::numeric_limits<double>::infinity()), 2e-3);
}

TEST(HertzRestitution, IsOneWithoutDampingAndFallsWithDamping)
{
    const double m = 3e-5, v = 0.5, e = 5e9, r = 6e-4;
    EXPECT_NEAR(hertz_restitution(m, v, e, r, 0.0), 1.0, 1e-6);
    const double tc = hertz_contact_time_s(m, v, e, r);
    EXPECT_LT(hertz_restitution(m, v, e, r, 0.01 * tc), hertz_restitution(m, v, e, r, 0.001 * tc));
}

TEST(HertzRestitution, DampingDerivedFromRestitutionReproducesIt)
{
    const double m = 3e-5, v = 0.5, e = 5e9, r = 6e-4;
    for (double target : {0.3, 0.5, 0.9}) {
        const double gamma = hertz_damping_for_restitution_s(target, m, v, e, r);
        EXPECT_NEAR(hertz_restitution(m, v, e, r, gamma), target, 1e-6) << "e = " << target;
    }
}

TEST(HertzRestitution, WeakDampingFollowsTheViscoelasticExpansion)
{
    // Viscoelastic spheres (Schwager & Pöschel 2008): 1 − e = C₁ γ_n α^{2/5} v^{1/5} + O(γ_n²).
    // So for weak damping the deficit doubles with γ_n and doubles when v grows 32-fold.
    const double m = 3e-5, v = 0.5, e = 5e9, r = 6e-4;
    const double tc = hertz_contact_time_s(m, v, e, r);
    const double gamma = 1e-4 * tc;
    const double d1 = 1.0 - hertz_restitution(m, v, e, r, gamma);
    const double d2 = 1.0 - hertz_restitution(m, v, e, r, 2.0 * gamma);
    const double d32 = 1.0 - hertz_restitution(m, 32.0 * v, e, r, gamma);
    EXPECT_NEAR(d2 / d1, 2.0, 0.01);
    EXPECT_NEAR(d32 / d1, 2.0, 0.01);
}

TEST(TangentialSpring, SticksBelowCoulombLimitWithForceProportionalToNormalForce)
{
    TangentialParams p;
    const Vec3 n = Vec3::UnitZ();
    const Vec3 vt(1e-3, 0.0, 0.0); // 1 mm/s for 1 µs: δ = 1 nm
    const TangentialResult r = tangential_force({}, n, vt, 2.0, p, 1e-6);
    EXPECT_TRUE(r.next.sticking);
    EXPECT_NEAR(r.next.spring_m.x(), 1e-9, 1e-24);
    EXPECT_NEAR(r.force_n.x(), -p.stiffness_per_m * 2.0 * 1e-9, 1e-20);
}

TEST(TangentialSpring, SlidesOnceCoulombLimitIsExceeded)
{
    TangentialParams p;
    const Vec3 n = Vec3::UnitZ();
    // A spring just below μ/k_t, then one more push takes it over the limit.
    TangentialState s{Vec3(0.999 * p.friction_coeff / p.stiffness_per_m, 0, 0), true};
    const Vec3 vt(1.0, 0.0, 0.0); // fast: Coulomb branch
    const TangentialResult r = tangential_force(s, n, vt, 2.0, p, 1e-6);
    EXPECT_FALSE(r.next.sticking);
    EXPECT_NEAR(r.force_n.x(), -p.friction_coeff * 2.0, 1e-12);
    // While sliding fast it keeps the Coulomb force along −v_t.
    const TangentialResult r2 = tangential_force(r.next, n, Vec3(0, 2.0, 0), 3.0, p, 1e-6);
    EXPECT_FALSE(r2.next.sticking);
    EXPECT_NEAR(r2.force_n.y(), -p.friction_coeff * 3.0, 1e-12);
}

TEST(TangentialSpring, BreaksAtCriticalSlipEvenBelowCoulombLimit)
{
    TangentialParams p;
    p.friction_coeff = 100.0; // Coulomb bound out of reach
    const TangentialState s{Vec3(0.999 * p.critical_slip_m, 0, 0), true};
    const TangentialResult r = tangential_force(s, Vec3::UnitZ(), Vec3(1.0, 0, 0), 1.0, p, 1e-6);
    EXPECT_FALSE(r.next.sticking);
}

TEST(TangentialSpring, SticksAgainWhenSlidingStops)
{
    TangentialParams p;
    const double slow = 0.5 * p.friction_coeff / p.damping_s_per_m; // γ_t |v_t| < μ
    const TangentialResult r = tangential_force({Vec3::Zero(), false}, Vec3::UnitZ(), Vec3(slow, 0, 0), 1.0, p, 1e-6);
    EXPECT_TRUE(r.next.sticking);
    EXPECT_NEAR(r.next.spring_m.x(), slow * 1e-6, 1e-18);
}

TEST(TangentialSpring, SticksAgainWhenTheSlipVelocityTurnsBackWhileSliding)
{
    // Sliding fast along +x (γ_t |v_t| = 2 > μ): Coulomb force along −x, and
    // the state remembers the slip of the step, v_t δt.
    TangentialParams p;
    const Vec3 n = Vec3::UnitZ();
    const double dt = 1e-6;
    const TangentialResult r = tangential_force({Vec3::Zero(), false}, n, Vec3(2e-3, 0, 0), 1.0, p, dt);
    EXPECT_FALSE(r.next.sticking);
    EXPECT_NEAR(r.force_n.x(), -p.friction_coeff, 1e-15);
    EXPECT_NEAR(r.next.spring_m.x(), 2e-3 * dt, 1e-21);
    // Still fast, but turned back: the slip velocity went through zero within
    // the step, so the sliding stopped; a new spring holds (δ_t = v_t δt).
    const Vec3 back(-1.5e-3, 0.2e-3, 0);
    const TangentialResult s = tangential_force(r.next, n, back, 1.0, p, dt);
    EXPECT_TRUE(s.next.sticking);
    EXPECT_NEAR((s.next.spring_m - back * dt).norm(), 0.0, 1e-21);
    EXPECT_NEAR((s.force_n + p.stiffness_per_m * 1.0 * back * dt).norm(), 0.0, 1e-15);
    // The same speed turned by less than 90° keeps sliding.
    const TangentialResult t = tangential_force(r.next, n, Vec3(0.1e-3, 1.5e-3, 0), 1.0, p, dt);
    EXPECT_FALSE(t.next.sticking);
}

TEST(TangentialSpring, ASlipThatTurnsBackFastStaysWithinTheCoulombBound)
{
    // Sliding along +x, then the slip turns back at 2 m/s within a 10 µs
    // step: a new spring would take δ_t = v_t δt = 20 µm, whose force
    // k_t F_n |δ_t| = 2 F_n is far above μ F_n. Like any sticking step it
    // must break instead: the force stays at μ F_n against the new slip.
    TangentialParams p;
    const Vec3 n = Vec3::UnitZ();
    const double dt = 1e-5, fn = 3.0;
    const TangentialResult r = tangential_force({Vec3::Zero(), false}, n, Vec3(1.0, 0, 0), fn, p, dt);
    ASSERT_FALSE(r.next.sticking);
    const TangentialResult s = tangential_force(r.next, n, Vec3(-2.0, 0, 0), fn, p, dt);
    EXPECT_FALSE(s.next.sticking);
    EXPECT_NEAR(s.force_n.x(), p.friction_coeff * fn, 1e-12);
    EXPECT_NEAR(s.force_n.norm(), p.friction_coeff * fn, 1e-12);
    // Its slip is remembered: turning back again at a speed whose spring
    // holds (1 mm/s: k_t |v_t| δt = 10⁻³ < μ) sticks.
    const TangentialResult t = tangential_force(s.next, n, Vec3(1e-3, 0, 0), fn, p, dt);
    EXPECT_TRUE(t.next.sticking);
    EXPECT_NEAR(t.force_n.x(), -p.stiffness_per_m * fn * 1e-3 * dt, 1e-15);
}

TEST(TangentialSpring, FollowsTheTangentPlaneAndKeepsItsLength)
{
    TangentialParams p;
    const Vec3 n = Vec3(0.0, 1.0, 1.0).normalized(); // the contact has turned
    const TangentialState s{Vec3(0.0, 1e-7, 0.0), true};
    const TangentialResult r = tangential_force(s, n, Vec3::Zero(), 1.0, p, 1e-6);
    EXPECT_NEAR(r.next.spring_m.dot(n), 0.0, 1e-20);
    EXPECT_NEAR(r.next.spring_m.norm(), 1e-7, 1e-20);
}
