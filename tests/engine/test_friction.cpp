// Sliding friction integrated at the auto time step: a sliding contact must
// stop and stick again however far one explicit step of Coulomb friction
// carries its slip velocity (engine/laws/tangential.hpp, top comment).
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

TEST(SlidingSphere, StopsAndSticksEvenWhenOneFrictionStepOvershootsTheStickWindow)
{
    // A grain (masses × 100, as in the preparation tests) pressed onto the
    // floor by a load P, no gravity and no normal damping, set sliding at
    // 0.1 m/s without spin. Its contact point's tangential mass is
    // m_t = m/3.5 (1/m_t = 1/m + r²/I with I = 2/5 m r²), so one explicit
    // step of Coulomb friction changes the slip speed by Δv = μ P δt / m_t.
    // The stick window |v_t| ≤ μ/γ_t is 2μ/γ_t wide; P is chosen so that
    // Δv is 6.6 times that (γ_t P δt / m_t = 13.2): the slip velocity steps
    // over the window. Before the reversal test the friction force then
    // flipped every step for ever (measured: sliding in all of the last
    // 20 000 steps, slip speed ~3 mm/s ≈ Δv); the sliding must stop instead.
    constexpr double radius_m = 1.23e-3;
    Simulation sim(1);
    World& w = sim.world;
    reset_world(w, Material{10e9, 0.3, 100.0 * 7800.0}, 1e-7);
    const std::uint8_t plate = add_material(w, Material{1e9, 0.3, 7800.0});
    add_wall(w, make_plate(0.0, +1.0, plate));
    add_grain(w, Vec3(0, 0, 2.0 * radius_m), radius_m, 0);
    // The auto step of a preparation (impact at ~1 m/s), with the grain away from the floor.
    set_time_step(w, stable_time_step(w, 1.0).auto_s);
    const double dt = w.dt_s;
    const double m = w.bodies[0].mass_kg[0], m_t = m / 3.5;
    const TangentialParams& tp = w.contact.tangential;
    const double load_n = 13.2 * m_t / (tp.damping_s_per_m * dt);
    const double window_m_per_s = tp.friction_coeff / tp.damping_s_per_m;
    const double dv_m_per_s = tp.friction_coeff * load_n * dt / m_t;
    ASSERT_GT(dv_m_per_s, 2.0 * window_m_per_s);
    // At rest at the static Hertz overlap under P, then set sliding.
    const double e_star = effective_modulus_pa(10e9, 0.3, 1e9, 0.3);
    const double overlap = std::pow(load_n / ((4.0 / 3.0) * e_star * std::sqrt(radius_m)), 2.0 / 3.0);
    place_body(w, BodyRef(BodyKind::grain, 0), Vec3(0, 0, radius_m - overlap));
    set_velocity(w, BodyRef(BodyKind::grain, 0), Vec3(0.1, 0, 0));
    w.point_loads.set(BodyRef(BodyKind::grain, 0), Vec3(0, 0, -load_n));

    // Coulomb friction stops the slip within v₀ / (μ P / m_t) ≈ 30 steps;
    // look at the last 20 000 of 40 000.
    const int steps = 40000;
    int sliding_steps = 0;
    double max_slip_m_per_s = 0.0;
    for (int s = 1; s <= steps; ++s) {
        ASSERT_FALSE(sim.step().blew_up) << "step " << s;
        if (s <= steps / 2) continue;
        const Vec3 v = w.bodies[0].x[1][0] / dt, omega = w.grain_rotation.theta[1][0] / dt;
        const Vec3 slip = v + omega.cross(Vec3(0, 0, -radius_m)); // contact point, floor at rest
        max_slip_m_per_s = std::max(max_slip_m_per_s, std::hypot(slip.x(), slip.y()));
        sliding_steps += !w.contacts.tangential[w.contacts.find({BodyKind::grain, 0}, wall_ref(0)).value()].sticking;
    }
    EXPECT_EQ(sliding_steps, 0);
    // It stuck with a slip speed below Δv (the speed turned back within one
    // step); the spring (no tangential damping) then keeps that energy,
    // ½ m_t v², so the slip speed stays below Δv (measured: 0.5 mm/s vs 4 mm/s).
    EXPECT_LT(max_slip_m_per_s, dv_m_per_s);
}
