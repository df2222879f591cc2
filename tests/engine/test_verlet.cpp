// Velocity Verlet on problems with exact solutions: free fall, the harmonic
// oscillator (bounded energy error, no drift: the scheme is symplectic), and
// the Hertz collision through the whole engine step.
#include "helpers.hpp"
#include "integrate/verlet.hpp"
#include "laws/hertz.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

using namespace wiredem::engine;

namespace {

/// Energy of a unit oscillator (k = m = 1) integrated with Verlet for `periods`
/// periods at `steps_per_period`; returns {largest |E − E₀|/E₀ over the first
/// period, the same over the last period}.
std::pair<double, double> oscillator_energy_error(int steps_per_period, int periods)
{
    const double dt = 2.0 * std::numbers::pi / steps_per_period;
    World w;
    w.dt_s = dt;
    w.integrator = Integrator::verlet;
    add_material(w, Material{});
    add_node(w, BodyKind::wire, Vec3(1, 0, 0), 1e-3, 1.0, 0);
    ThreadPool pool(1);
    auto& body = w.bodies[1];
    body.x[2][0] = 0.5 * dt * dt * Vec3(-1, 0, 0);
    std::pair<double, double> worst{0.0, 0.0};
    for (int s = 0; s < steps_per_period * periods; ++s) {
        verlet_first_half(w, pool);
        body.force_n[0] = -body.x[0][0];
        EXPECT_TRUE(verlet_second_half(w, pool));
        const double e = 0.5 * (body.x[1][0] / dt).squaredNorm() + 0.5 * body.x[0][0].squaredNorm();
        const double err = std::abs(e - 0.5) / 0.5;
        if (s < steps_per_period) worst.first = std::max(worst.first, err);
        if (s >= steps_per_period * (periods - 1)) worst.second = std::max(worst.second, err);
    }
    return worst;
}

} // namespace

TEST(Verlet, FreeFallIsExact)
{
    // Verlet integrates a constant acceleration exactly.
    const Vec3 v0(0.3, 0.0, 1.0);
    for (double dt : {1e-3, 1e-5}) {
        Simulation sim(1);
        sim.world.dt_s = dt;
        sim.world.integrator = Integrator::verlet;
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

TEST(Verlet, OscillatorEnergyStaysBoundedWithoutDrift)
{
    // The velocity-Verlet energy of x'' = −x oscillates with relative amplitude
    // (ω δt)²/4 (the shadow Hamiltonian) and does not drift: the worst error in
    // the 2000th period equals the worst in the first.
    const int n = 50;
    const double omega_dt = 2.0 * std::numbers::pi / n;
    const auto [first, last] = oscillator_energy_error(n, 2000);
    EXPECT_LT(first, 0.25 * omega_dt * omega_dt * 1.05);
    EXPECT_GT(first, 0.25 * omega_dt * omega_dt * 0.8); // the error is really there: the check can see it
    EXPECT_NEAR(last, first, 0.01 * first);
}

TEST(Verlet, StableJustBelowOmegaDtTwo)
{
    // The linear stability bound of Verlet is ω δt < 2: bounded at 1.9 over
    // 10⁵ steps, growing without bound at 2.05.
    auto amplitude = [](double omega_dt) {
        World w;
        w.dt_s = omega_dt;
        w.integrator = Integrator::verlet;
        add_material(w, Material{});
        add_node(w, BodyKind::wire, Vec3(1, 0, 0), 1e-3, 1.0, 0);
        ThreadPool pool(1);
        auto& body = w.bodies[1];
        body.x[2][0] = 0.5 * omega_dt * omega_dt * Vec3(-1, 0, 0);
        for (int s = 0; s < 100000 && body.x[0][0].norm() < 1e6; ++s) {
            verlet_first_half(w, pool);
            body.force_n[0] = -body.x[0][0];
            (void)verlet_second_half(w, pool);
        }
        return body.x[0][0].norm();
    };
    EXPECT_LT(amplitude(1.9), 10.0);
    EXPECT_GT(amplitude(2.05), 1e6);
}

TEST(Verlet, SwitchingIntegratorKeepsPositionVelocityAndAcceleration)
{
    World w;
    w.dt_s = 1e-4;
    add_material(w, Material{});
    add_grain(w, Vec3(1, 2, 3), 1e-3, 0, Vec3(4, 5, 6));
    for (int k = 2; k < gear_order; ++k) w.bodies[0].x[k][0] = Vec3::Constant(k);
    set_integrator(w, Integrator::verlet);
    EXPECT_EQ(w.integrator, Integrator::verlet);
    EXPECT_EQ(w.bodies[0].x[0][0], Vec3(1, 2, 3));
    EXPECT_EQ(w.bodies[0].x[1][0], Vec3(4, 5, 6) * 1e-4);
    EXPECT_EQ(w.bodies[0].x[2][0], Vec3::Constant(2));
    for (int k = 3; k < gear_order; ++k) EXPECT_EQ(w.bodies[0].x[k][0], Vec3::Zero()) << "x" << k;
}
