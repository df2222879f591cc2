// One binary impact run through the whole engine (contact list, the SIMD
// contact kernel, the gather, the integrators), and the closed forms it is
// measured against: the benchmarks of Chung & Ooi, "Benchmark tests for
// verifying discrete element modelling codes at particle impact level",
// Granular Matter 13 (2011) 643–656 (docs/validation.md).
//
// Geometry: the contact normal n is +z. Body 1, a grain, comes down onto the
// target from above: a plate (a floor at z = 0), a second grain, or a membrane
// node (a point mass with a contact radius, no rotation). Tangential motion is
// along x, spins about y, so every impact is planar.
#pragma once

#include "laws/hertz.hpp"
#include "simulation.hpp"
#include "state/world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace wiredem::engine::validation {

enum class Target { plate, grain, membrane_node };

struct ImpactCase {
    Material material1;                    ///< the grain
    double radius1_m = 0.0;
    Target target = Target::plate;
    Material material2;                    ///< the plate's, the second grain's, or the node's material
    double radius2_m = 0.0;                ///< second grain or node (contact radius); unused for a plate
    double node_mass_kg = 0.0;             ///< membrane node only
    Vec3 velocity1_m_per_s = Vec3::Zero(); ///< body 1 (z < 0: approaching)
    Vec3 velocity2_m_per_s = Vec3::Zero(); ///< body 2 (not for a plate)
    double spin1_rad_per_s = 0.0;          ///< body 1 about y
    double spin2_rad_per_s = 0.0;          ///< body 2 about y (a grain)
    double friction_coeff = 0.0;           ///< μ
    double restitution = 1.0;              ///< e_n at this impact's normal speed; 1: no damping
    Integrator integrator = Integrator::gear5;
    double steps_per_contact = 2000.0;     ///< δt = t_c / this
};

[[nodiscard]] inline double sphere_mass_of(const Material& m, double radius_m)
{
    return m.density_kg_per_m3 * 4.0 / 3.0 * std::numbers::pi * radius_m * radius_m * radius_m;
}

/// Mass and moment of inertia of each body (an infinite mass for the plate, no
/// rotation for a node: 1/I = 0).
struct Inertias {
    double inv_mass1 = 0.0, inv_inertia1 = 0.0, inv_mass2 = 0.0, inv_inertia2 = 0.0;
};

[[nodiscard]] inline Inertias inertias_of(const ImpactCase& c)
{
    Inertias k;
    const double m1 = sphere_mass_of(c.material1, c.radius1_m);
    k.inv_mass1 = 1.0 / m1;
    k.inv_inertia1 = 1.0 / (0.4 * m1 * c.radius1_m * c.radius1_m);
    if (c.target == Target::grain) {
        const double m2 = sphere_mass_of(c.material2, c.radius2_m);
        k.inv_mass2 = 1.0 / m2;
        k.inv_inertia2 = 1.0 / (0.4 * m2 * c.radius2_m * c.radius2_m);
    } else if (c.target == Target::membrane_node) {
        k.inv_mass2 = 1.0 / c.node_mass_kg;
    }
    return k;
}

/// The pair's Hertz constants: reduced mass, E*, R*, and the approach speed.
struct PairConstants {
    double reduced_mass_kg, eff_modulus_pa, eff_radius_m, approach_speed_m_per_s;
};

[[nodiscard]] inline PairConstants pair_constants(const ImpactCase& c)
{
    const Inertias k = inertias_of(c);
    const double r2 = c.target == Target::plate ? std::numeric_limits<double>::infinity() : c.radius2_m;
    return {1.0 / (k.inv_mass1 + k.inv_mass2),
        effective_modulus_pa(c.material1.youngs_modulus_pa, c.material1.poisson_ratio, c.material2.youngs_modulus_pa,
            c.material2.poisson_ratio),
        effective_radius_m(c.radius1_m, r2), c.velocity2_m_per_s.z() - c.velocity1_m_per_s.z()};
}

/// What an impact gives: the state after the contact has ended, and the
/// extremes during it.
struct ImpactResult {
    Vec3 velocity1_m_per_s = Vec3::Zero(), velocity2_m_per_s = Vec3::Zero();
    double spin1_rad_per_s = 0.0, spin2_rad_per_s = 0.0;
    double contact_time_s = 0.0;
    double max_overlap_m = 0.0;
    double max_normal_force_n = 0.0;
    double energy_before_j = 0.0, energy_after_j = 0.0;  ///< translational + rotational
};

/// Kinetic energy of the two bodies for given velocities and spins.
[[nodiscard]] inline double impact_energy_j(const ImpactCase& c, const Vec3& v1, double w1, const Vec3& v2, double w2)
{
    const Inertias k = inertias_of(c);
    double e = 0.5 * v1.squaredNorm() / k.inv_mass1 + 0.5 * w1 * w1 / k.inv_inertia1;
    if (k.inv_mass2 > 0.0) e += 0.5 * v2.squaredNorm() / k.inv_mass2;
    if (k.inv_inertia2 > 0.0) e += 0.5 * w2 * w2 / k.inv_inertia2;
    return e;
}

/// Runs the impact through the engine on one thread: the bodies start a few
/// steps apart and run until the contact has ended.
[[nodiscard]] inline ImpactResult run_impact(const ImpactCase& c)
{
    const PairConstants pc = pair_constants(c);
    const double tc = hertz_contact_time_s(pc.reduced_mass_kg, pc.approach_speed_m_per_s, pc.eff_modulus_pa, pc.eff_radius_m);
    const double dt = tc / c.steps_per_contact;

    Simulation sim(1);
    World& w = sim.world;
    w = World{};
    w.gravity_m_per_s2 = Vec3::Zero();
    w.integrator = c.integrator;
    w.dt_s = dt;
    w.contact.tangential.friction_coeff = c.friction_coeff;
    w.contact.normal_damping_s = c.restitution < 1.0
        ? hertz_damping_for_restitution_s(
              c.restitution, pc.reduced_mass_kg, pc.approach_speed_m_per_s, pc.eff_modulus_pa, pc.eff_radius_m)
        : 0.0;
    const std::uint8_t m1 = add_material(w, c.material1);
    const std::uint8_t m2 = add_material(w, c.material2);
    // Touch after about ten steps. Against a body, the centres line up at
    // mid-contact: the normal then turns as much one way as the other while
    // the bodies pass, and its first-order share of the tangential impulse
    // cancels (otherwise a tilt of v_t t_c / 2(R₁ + R₂) puts a share of J_n
    // into J_t: a few per cent of μ J_n at the benchmarks' speeds).
    const double gap_m = 10.0 * pc.approach_speed_m_per_s * dt;
    const double z2 = c.target == Target::plate ? 0.0 : -c.radius2_m;
    const double mid_contact_s = gap_m / pc.approach_speed_m_per_s + 0.5 * tc;
    const double x_offset_m = c.target == Target::plate
        ? 0.0 : -(c.velocity1_m_per_s.x() - c.velocity2_m_per_s.x()) * mid_contact_s;
    const Vec3 x1(x_offset_m, 0, c.radius1_m + gap_m);
    add_grain(w, x1, c.radius1_m, m1, c.velocity1_m_per_s, Vec3(0, c.spin1_rad_per_s, 0));
    switch (c.target) {
    case Target::plate: add_wall(w, make_plate(0.0, +1.0, m2)); break;
    case Target::grain:
        add_grain(w, Vec3(0, 0, z2), c.radius2_m, m2, c.velocity2_m_per_s, Vec3(0, c.spin2_rad_per_s, 0));
        break;
    case Target::membrane_node:
        add_node(w, BodyKind::membrane, Vec3(0, 0, z2), c.radius2_m, c.node_mass_kg, m2, c.velocity2_m_per_s);
        break;
    }

    const BodyRef b1(BodyKind::grain, 0);
    const BodyRef b2(c.target == Target::membrane_node ? BodyKind::membrane : BodyKind::grain,
        c.target == Target::membrane_node ? 0u : 1u);
    const auto overlap_m = [&] {
        const Vec3 p1 = w.bodies[0].x[0][0];
        if (c.target == Target::plate) return c.radius1_m - p1.z();
        const Vec3 p2 = w.bodies[static_cast<int>(b2.kind())].x[0][b2.index()];
        return c.radius1_m + c.radius2_m - (p1 - p2).norm();
    };

    ImpactResult r;
    r.energy_before_j = impact_energy_j(c, c.velocity1_m_per_s, c.spin1_rad_per_s, c.velocity2_m_per_s, c.spin2_rad_per_s);
    bool started = false;
    const auto max_steps = static_cast<long>(100.0 * c.steps_per_contact);
    for (long s = 0; s < max_steps; ++s) {
        sim.step();
        const double force = w.force_of(BodyKind::grain)[0].norm();
        if (force > 0.0) {
            started = true;
            r.contact_time_s += dt;
            r.max_normal_force_n = std::max(r.max_normal_force_n, std::abs(w.force_of(BodyKind::grain)[0].z()));
            r.max_overlap_m = std::max(r.max_overlap_m, overlap_m());
        } else if (started && overlap_m() < 0.0) {
            break;
        }
    }
    r.velocity1_m_per_s = velocity_m_per_s(w, b1);
    r.spin1_rad_per_s = angular_velocity_rad_per_s(w, 0).y();
    if (c.target != Target::plate) r.velocity2_m_per_s = velocity_m_per_s(w, b2);
    if (c.target == Target::grain) r.spin2_rad_per_s = angular_velocity_rad_per_s(w, 1).y();
    r.energy_after_j = impact_energy_j(c, r.velocity1_m_per_s, r.spin1_rad_per_s, r.velocity2_m_per_s, r.spin2_rad_per_s);
    return r;
}

/// Slip velocity (along x) of body 1's contact point relative to body 2's:
/// body 1's point is at −R₁ n from its centre, body 2's at +R₂ n, so with
/// spins about y, s = v₁ₓ − ω₁R₁ − v₂ₓ − ω₂R₂.
[[nodiscard]] inline double slip_m_per_s(const ImpactCase& c, const Vec3& v1, double w1, const Vec3& v2, double w2)
{
    const double r2 = c.target == Target::grain ? c.radius2_m : 0.0;
    return v1.x() - w1 * c.radius1_m - v2.x() - w2 * r2;
}

/// The rigid-body answer of an impact with Coulomb friction (Maw, Barber &
/// Fawcett 1976; Chung & Ooi's "rigid-body" lines): normal impulse
/// J_n = (1 + e) m* v_n; a tangential impulse J_t opposing the slip s, with
/// Δs = J_t / m_t, 1/m_t = 1/m₁ + R₁²/I₁ + 1/m₂ + R₂²/I₂ (terms absent for a
/// plate or a node that does not turn). While |s₀| ≥ μ J_n / m_t the contact
/// slides throughout and J_t = −μ J_n sign(s₀), whatever the tangential
/// stiffness; below, a rigid contact ends sticking (s = 0).
struct RigidBodyImpact {
    Vec3 velocity1_m_per_s = Vec3::Zero(), velocity2_m_per_s = Vec3::Zero();
    double spin1_rad_per_s = 0.0, spin2_rad_per_s = 0.0;
    bool slides_throughout = false;
};

[[nodiscard]] inline RigidBodyImpact rigid_body_impact(const ImpactCase& c)
{
    const PairConstants pc = pair_constants(c);
    const Inertias k = inertias_of(c);
    const double jn = (1.0 + c.restitution) * pc.reduced_mass_kg * pc.approach_speed_m_per_s;
    const double r2 = c.target == Target::grain ? c.radius2_m : 0.0;
    const double inv_mt = k.inv_mass1 + c.radius1_m * c.radius1_m * k.inv_inertia1 + k.inv_mass2 + r2 * r2 * k.inv_inertia2;
    const double s0 = slip_m_per_s(c, c.velocity1_m_per_s, c.spin1_rad_per_s, c.velocity2_m_per_s, c.spin2_rad_per_s);
    RigidBodyImpact out;
    out.slides_throughout = std::abs(s0) >= c.friction_coeff * jn * inv_mt;
    const double jt = out.slides_throughout ? -std::copysign(c.friction_coeff * jn, s0) : -s0 / inv_mt;
    // J = (J_t, 0, J_n) on body 1, −J on body 2. Torque of J_t at −R₁ n about
    // y: (−R₁ ẑ × J_t x̂)_y = −R₁ J_t; on body 2, at +R₂ n: (R₂ ẑ × (−J_t x̂))_y = −R₂ J_t.
    out.velocity1_m_per_s = c.velocity1_m_per_s + k.inv_mass1 * Vec3(jt, 0, jn);
    out.velocity2_m_per_s = c.velocity2_m_per_s - k.inv_mass2 * Vec3(jt, 0, jn);
    out.spin1_rad_per_s = c.spin1_rad_per_s - k.inv_inertia1 * c.radius1_m * jt;
    out.spin2_rad_per_s = c.spin2_rad_per_s - k.inv_inertia2 * r2 * jt;
    return out;
}

/// How far a finite contact may stray from the rigid-body answer, relative to
/// the friction impulse μ J_n (and, for a spin, to its change), where the
/// contact slides throughout: the rigid-body theory takes the contact as an
/// instant at a fixed normal with lever arms R.
struct FiniteContactTolerance {
    /// The normal turns as the bodies pass. run_impact lines the centres up at
    /// mid-contact for a constant relative speed u₀; friction changes it by
    /// Δu = |J_t| (1/m₁ + 1/m₂), which moves the line-up by at most
    /// Δu t_c / 2, a tilt of Δu t_c / 2(R₁ + R₂) that puts that share of J_n
    /// into the tangential impulse: Δu t_c / (2 μ (R₁ + R₂)) of μ J_n. None on
    /// a plate.
    double impulse = 0.0;
    /// The engine's lever arm is r − ξ/2 (docs/model.md, "Torques"): the
    /// torque's impulse is short by up to ξ_max / 2R of the spin's change.
    double lever1 = 0.0, lever2 = 0.0;
};

[[nodiscard]] inline FiniteContactTolerance finite_contact_tolerance(const ImpactCase& c)
{
    const PairConstants pc = pair_constants(c);
    const Inertias k = inertias_of(c);
    const double xi = hertz_max_overlap_m(pc.reduced_mass_kg, pc.approach_speed_m_per_s, pc.eff_modulus_pa, pc.eff_radius_m);
    FiniteContactTolerance t;
    t.lever1 = 0.5 * xi / c.radius1_m;
    if (c.target == Target::grain) t.lever2 = 0.5 * xi / c.radius2_m;
    if (c.target != Target::plate && c.friction_coeff > 0.0) {
        const double tc = hertz_contact_time_s(pc.reduced_mass_kg, pc.approach_speed_m_per_s, pc.eff_modulus_pa, pc.eff_radius_m);
        const double jt = c.friction_coeff * (1.0 + c.restitution) * pc.reduced_mass_kg * pc.approach_speed_m_per_s;
        const double du = jt * (k.inv_mass1 + k.inv_mass2);
        t.impulse = du * tc / (2.0 * c.friction_coeff * (c.radius1_m + c.radius2_m));
    }
    return t;
}

/// The relative shortfall of the friction impulse against μ J_n in a contact
/// that slides throughout, from the spring phase at its start: the paper's
/// law sticks until the spring holds μ F_n, i.e. for the first μ/k_t of slip
/// (k_t F_n δ_t = μ F_n), a time t_s = μ / (k_t |s₀|) during which the force is
/// below μ F_n. With F_n ≤ K (v_n t)^{3/2} early in the contact
/// (K = 4/3 E* √R*), the missing impulse is at most μ K v_n^{3/2} t_s^{5/2} / (5/2),
/// against μ J_n = μ (1 + e) m* v_n.
[[nodiscard]] inline double spring_phase_shortfall(const ImpactCase& c, double stiffness_per_m)
{
    const PairConstants pc = pair_constants(c);
    const double s0 = std::abs(slip_m_per_s(c, c.velocity1_m_per_s, c.spin1_rad_per_s, c.velocity2_m_per_s, c.spin2_rad_per_s));
    const double ts = c.friction_coeff / (stiffness_per_m * s0);
    const double kh = 4.0 / 3.0 * pc.eff_modulus_pa * std::sqrt(pc.eff_radius_m);
    const double missing = kh * std::pow(pc.approach_speed_m_per_s, 1.5) * std::pow(ts, 2.5) / 2.5;
    return missing / ((1.0 + c.restitution) * pc.reduced_mass_kg * pc.approach_speed_m_per_s);
}

} // namespace wiredem::engine::validation
