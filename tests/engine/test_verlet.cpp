// Velocity Verlet on problems with exact solutions (free fall: in
// test_gear5.cpp, for both integrators): the harmonic oscillator (bounded energy error, no drift: the scheme is symplectic), and
// the Hertz collision through the whole engine step.
#include "helpers.hpp"
#include "integrate/verlet.hpp"
#include "laws/hertz.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

using namespace wiredem::engine;

namespace {

/// A unit oscillator x'' = −x (k = m = 1) starting at x = (1, 0, 0) at rest,
/// stepped with Verlet's two halves and the spring force between them.
class UnitOscillator {
public:
    /// ζ: damping ratio of a dashpot −2ζ v on the half-step velocity (what
    /// the engine's damped contacts and wire see).
    explicit UnitOscillator(double dt, double zeta = 0.0) : zeta_(zeta)
    {
        w_.dt_s = dt;
        w_.integrator = Integrator::verlet;
        add_material(w_, Material{});
        add_node(w_, BodyKind::wire, Vec3(1, 0, 0), 1e-3, 1.0, 0);
        body().x[2][0] = 0.5 * dt * dt * Vec3(-1, 0, 0); // a(0) = −x(0)
    }
    /// One step; false if the state became non-finite.
    bool step()
    {
        verlet_first_half(w_, pool_);
        w_.body_force_n[1][0] = -body().x[0][0] - 2.0 * zeta_ * body().x[1][0] / w_.dt_s;
        return verlet_second_half(w_, pool_);
    }
    [[nodiscard]] const Vec3& x() { return body().x[0][0]; }
    [[nodiscard]] double energy() { return 0.5 * (body().x[1][0] / w_.dt_s).squaredNorm() + 0.5 * x().squaredNorm(); }

private:
    TranslationalState& body() { return w_.bodies[1]; }
    double zeta_ = 0.0;
    World w_;
    ThreadPool pool_{1};
};

/// Largest |E − E₀|/E₀ over the first and over the last of `periods` periods
/// at `steps_per_period`.
std::pair<double, double> oscillator_energy_error(int steps_per_period, int periods)
{
    UnitOscillator osc(2.0 * std::numbers::pi / steps_per_period);
    std::pair<double, double> worst{0.0, 0.0};
    for (int s = 0; s < steps_per_period * periods; ++s) {
        EXPECT_TRUE(osc.step());
        const double err = std::abs(osc.energy() - 0.5) / 0.5;
        if (s < steps_per_period) worst.first = std::max(worst.first, err);
        if (s >= steps_per_period * (periods - 1)) worst.second = std::max(worst.second, err);
    }
    return worst;
}

} // namespace

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
        UnitOscillator osc(omega_dt);
        for (int s = 0; s < 100000 && osc.x().norm() < 1e6; ++s) (void)osc.step();
        return osc.x().norm();
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

TEST(Verlet, DampedStabilityLimitIsTheExactOne)
{
    // With a dashpot −2ζ v the bound falls to ω δt = 2 (√(1 + ζ²) − ζ); the
    // time step uses it where it is below the accuracy bound 0.3 (ζ > 3.2).
    auto amplitude = [](double omega_dt, double zeta) {
        UnitOscillator osc(omega_dt, zeta);
        for (int s = 0; s < 100000 && osc.x().norm() < 1e6; ++s) (void)osc.step();
        return osc.x().norm();
    };
    for (double zeta : {0.5, 4.0, 20.0}) {
        const double exact = 2.0 * (std::sqrt(1.0 + zeta * zeta) - zeta);
        EXPECT_LT(amplitude(0.98 * exact, zeta), 10.0) << "ζ = " << zeta;
        EXPECT_GT(amplitude(1.02 * exact, zeta), 1e6) << "ζ = " << zeta;
    }
    EXPECT_EQ(damped_stability_limit(Integrator::verlet, 0.5), gear5_stability_limit);
    EXPECT_DOUBLE_EQ(damped_stability_limit(Integrator::verlet, 20.0), 2.0 * (std::sqrt(401.0) - 20.0));
}
