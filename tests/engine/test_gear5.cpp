// Gear-5 on problems with exact solutions: free fall (both integrators), the harmonic oscillator.
#include "helpers.hpp"
#include "integrate/gear5.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

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
    w.bodies[1].x[2][0] = 0.5 * dt * dt * force(x0); // start from the true acceleration
    for (int s = 0; s < steps; ++s) {
        gear5_predict(w, pool);
        w.body_force_n[1][0] = force(w.bodies[1].x[0][0]);
        (void)gear5_correct(w, pool);
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
