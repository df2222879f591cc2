// Gear-5 on problems with exact solutions: free fall (both integrators), the harmonic oscillator.
#include "helpers.hpp"
#include "integrate/gear5.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <type_traits>

using namespace wiredem::engine;

namespace {

/// One free body (no contacts) with a prescribed force law, integrated with
/// Gear-5 for `steps` steps.
template <class Force>
Vec3 integrate_single(double dt, int steps, const Vec3& x0, const Vec3& v0, Force force, double* max_energy_error = nullptr)
{
    World w;
    w.dt_s = dt;
    add_material(w, Material{});
    add_node(w, BodyKind::wire, x0, 1e-3, 1.0, 0, v0);
    ThreadPool pool(1);
    if constexpr (std::is_invocable_v<Force, const Vec3&, const Vec3&>) // start from the true acceleration
        w.bodies[1].x[2][0] = 0.5 * dt * dt * force(x0, v0);
    else
        w.bodies[1].x[2][0] = 0.5 * dt * dt * force(x0);
    for (int s = 0; s < steps; ++s) {
        gear5_predict(w, pool);
        // A force of the position, or of the position and the predicted
        // velocity (what the engine's damped contacts and wire see).
        if constexpr (std::is_invocable_v<Force, const Vec3&, const Vec3&>)
            w.body_force_n[1][0] = force(w.bodies[1].x[0][0], Vec3(w.bodies[1].x[1][0] / dt));
        else
            w.body_force_n[1][0] = force(w.bodies[1].x[0][0]);
        (void)gear5_correct(w, pool);
        ++w.step_count; // as step() counts it: the next predict takes the corrector's prediction
        if (max_energy_error) {
            const Vec3 x = w.bodies[1].x[0][0], v = w.bodies[1].x[1][0] / dt;
            const double e = 0.5 * v.squaredNorm() + 0.5 * x.squaredNorm(); // k = m = 1
            const double e0 = 0.5 * v0.squaredNorm() + 0.5 * x0.squaredNorm();
            *max_energy_error = std::max(*max_energy_error, std::abs(e - e0) / e0);
        }
    }
    return w.bodies[1].x[0][0];
}

} // namespace

class FreeFall : public ::testing::TestWithParam<Integrator> {};

INSTANTIATE_TEST_SUITE_P(Integrators, FreeFall, ::testing::Values(Integrator::gear5, Integrator::verlet),
    [](const ::testing::TestParamInfo<Integrator>& i) { return i.param == Integrator::gear5 ? "Gear5" : "Verlet"; });

TEST_P(FreeFall, MatchesTheParabolaAtThreeStepSizes)
{
    // Through the whole engine step, which must start the integrator from the
    // true acceleration: both schemes are then exact for a quadratic.
    const Vec3 v0(0.3, 0.0, 1.0);
    for (double dt : {1e-3, 1e-4, 1e-5}) {
        Simulation sim(1);
        sim.world.integrator = GetParam();
        sim.world.dt_s = dt;
        sim.world.gravity_m_per_s2 = Vec3(0.0, 0.0, -9.81);
        add_material(sim.world, Material{});
        add_grain(sim.world, Vec3::Zero(), 1e-3, 0, v0);
        const int steps = static_cast<int>(std::lround(0.1 / dt));
        sim.run(steps);
        const double t = steps * dt;
        const Vec3 exact = v0 * t + 0.5 * sim.world.gravity_m_per_s2 * t * t;
        EXPECT_NEAR((sim.world.bodies[0].x[0][0] - exact).norm(), 0.0, 1e-12) << "dt = " << dt;
        EXPECT_NEAR((velocity_m_per_s(sim.world, {BodyKind::grain, 0}) - v0 - sim.world.gravity_m_per_s2 * t).norm(), 0.0, 1e-10);
    }
}

TEST(Gear5, HarmonicOscillatorKeepsPhaseAndEnergyAtFiftyStepsPerPeriod)
{
    // k = m = 1: x(t) = cos t. 50 steps a period, 20 periods.
    const double dt = 2.0 * std::numbers::pi / 50.0;
    const int steps = 50 * 20;
    double energy_error = 0.0;
    const Vec3 x = integrate_single(
        dt, steps, Vec3(1, 0, 0), Vec3::Zero(), [](const Vec3& p) { return Vec3(-p); }, &energy_error);
    EXPECT_NEAR(x.x(), std::cos(steps * dt), 1e-3);
    EXPECT_LT(energy_error, 1e-3);
}

TEST(Gear5, StabilityLimitUsedByTheTimeStepHolds)
{
    // Bounded just below the documented limit ω δt, unbounded a little above it.
    auto grows = [](double omega_dt) {
        const Vec3 x = integrate_single(omega_dt, 200000, Vec3(1, 0, 0), Vec3::Zero(), [](const Vec3& p) { return Vec3(-p); });
        return !(x.norm() < 2.0);
    };
    EXPECT_FALSE(grows(0.95 * gear5_stability_limit));
    EXPECT_TRUE(grows(1.25 * gear5_stability_limit));
}

TEST(Gear5, DampedStabilityLimitUsedByTheTimeStepHolds)
{
    // x'' = −x − 2ζ x' (ω = 1): bounded for 2·10⁵ steps at the bound the time
    // step uses, for light to heavy damping. Where damping sets the bound
    // (ζ ≥ 0.3: c δt/m, not ω δt) the undamped bound 0.3 is unstable, and 1.3
    // times the bound is too: the bound is damping's, and tight.
    auto grows = [](double omega_dt, double zeta) {
        const Vec3 x = integrate_single(omega_dt, 200000, Vec3(1, 0, 0), Vec3::Zero(),
            [zeta](const Vec3& p, const Vec3& v) { return Vec3(-p - 2.0 * zeta * v); });
        return !(x.norm() < 2.0);
    };
    for (double zeta : {0.1, 0.2, 0.3, 0.5, 1.0, 5.0}) {
        const double bound = damped_stability_limit(Integrator::gear5, zeta);
        EXPECT_LE(bound, gear5_stability_limit);
        EXPECT_FALSE(grows(bound, zeta)) << "ζ = " << zeta;
        if (zeta >= 0.3) {
            EXPECT_TRUE(grows(gear5_stability_limit, zeta)) << "ζ = " << zeta;
            EXPECT_TRUE(grows(1.3 * bound, zeta)) << "ζ = " << zeta;
        }
    }
    EXPECT_EQ(damped_stability_limit(Integrator::gear5, 0.0), gear5_stability_limit);
}

// The integrators' blow-up check is folded into their last loop (Gear-5's
// corrector, Verlet's kick): a force that turns infinite or NaN between two
// steps must be reported by the step that takes it, for both integrators
// (Verlet's positions are still finite then: its velocity is the first to
// go), and a finite run reports nothing.
TEST(Integrators, ANonFiniteForceIsReportedByTheStepThatTakesIt)
{
    for (const Integrator integrator : {Integrator::gear5, Integrator::verlet})
        for (const double bad : {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
            Simulation sim(1);
            World& w = sim.world;
            w.integrator = integrator;
            w.dt_s = 1e-5;
            add_material(w, Material{});
            for (int i = 0; i < 300; ++i) add_grain(w, Vec3(0.01 * i, 0.0, 0.0), 1e-3, 0); // apart, falling
            for (int s = 0; s < 5; ++s) ASSERT_FALSE(sim.step().blew_up) << "step " << s;
            w.point_loads.set(BodyRef(BodyKind::grain, 217), Vec3(0.0, bad, 0.0));
            EXPECT_TRUE(sim.step().blew_up) << (integrator == Integrator::gear5 ? "gear5 " : "verlet ") << bad;
        }
}
