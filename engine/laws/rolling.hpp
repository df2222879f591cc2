// Rolling resistance (issue 40, part 2): the elastic–plastic spring–dashpot
// law, type C of Ai, Chen, Rotter & Ooi, Powder Technology 206 (2011) 269,
// which LIGGGHTS' `epsd2` and PFC's `rrlinear` follow. A rolling spring
// between the two bodies resists their relative rolling rotation θ_r (the
// relative rotation about axes in the tangent plane; twisting about the
// normal is left free) with the torque
//
//     M_r = −k_r θ_r,  k_r = f_r k_t F_n R*²   (the tangential spring's
//                                               stiffness k_t F_n times R*²)
//
// until it reaches the limit M_max = μ_r R* F_n; beyond it the spring slips
// (full mobilisation: θ_r is held at the limit angle, M_r = M_max against the
// rolling). While below the limit a viscous torque −C_r ω_r adds to it,
// C_r = 2 η_r √(I_r k_r) with I_r the bodies' rotational inertia about the
// contact point, and none at full mobilisation (Ai et al.'s f = 0); the sum
// is bounded by M_max too. Since k_r and M_max are both ∝ F_n, the limit is
// an angle, θ_lim = M_max/k_r = μ_r/(f_r k_t R*), whatever F_n (a contact
// without load slips at the same angle), so the state kept is the angle θ_r
// [rad], as the tangential law keeps its δ_t, turned into the current
// tangent plane each step. docs/model.md, "Rolling resistance", derives it.
#pragma once

#include "core/types.hpp"

#include <cmath>

namespace wiredem::engine {

/// Parameters of the rolling law, shared by all contacts. μ_r = 0: off.
/// The defaults are the model's (none: the model spec has no rolling
/// resistance) and the job spec's (ContactSpec holds these; its ranges:
/// api/job_spec.cpp).
struct RollingParams {
    double friction_coeff = 0.0;   ///< μ_r: M_max = μ_r R* F_n; 0 turns the law off
    double stiffness_factor = 1.0; ///< f_r: k_r = f_r k_t F_n R*² (Ai et al.'s k_r = k_t R*² at 1)
    double damping_ratio = 0.0;    ///< η_r: C_r = 2 η_r √(I_r k_r) below the limit
    [[nodiscard]] bool on() const { return friction_coeff > 0.0; }
    friend bool operator==(const RollingParams&, const RollingParams&) = default;
};

struct RollingResult {
    Vec3 torque_n_m;  ///< M_r on the first body (−M_r on the second) [N·m]
    Vec3 next_rad;    ///< θ_r to keep for the next step [rad]
};

/// One step of the rolling law.
/// @param prev_rad              θ_r after the previous step [rad]
/// @param normal                unit normal of the contact
/// @param relative_spin_rad_per_s  ω_first − ω_second [rad/s]; only its part in
///                              the tangent plane rolls
/// @param normal_force_n        F_n ≥ 0 [N]
/// @param eff_radius_m          R* [m] (r against a wall)
/// @param tangential_stiffness_per_m  k_t [1/m] (TangentialParams)
/// @param rolling_inertia_kg_m2 I_r [kg·m²], for the damping only
/// @param dt_s                  time step [s]
[[nodiscard]] inline RollingResult rolling_torque(const Vec3& prev_rad, const Vec3& normal,
    const Vec3& relative_spin_rad_per_s, double normal_force_n, double eff_radius_m, double tangential_stiffness_per_m,
    double rolling_inertia_kg_m2, const RollingParams& p, double dt_s) noexcept
{
    const Vec3 rolling = relative_spin_rad_per_s - relative_spin_rad_per_s.dot(normal) * normal; // ω_r
    // The spring in the current tangent plane (normal part dropped, length kept), plus this step's rolling.
    Vec3 theta = prev_rad - prev_rad.dot(normal) * normal;
    const double len2 = theta.squaredNorm();
    if (len2 > 0.0) theta *= std::sqrt(prev_rad.squaredNorm() / len2);
    theta += rolling * dt_s;

    const double k_r = p.stiffness_factor * tangential_stiffness_per_m * normal_force_n * eff_radius_m * eff_radius_m;
    const double m_max = p.friction_coeff * eff_radius_m * normal_force_n;
    const double limit_rad = p.friction_coeff / (p.stiffness_factor * tangential_stiffness_per_m * eff_radius_m);
    const double angle2 = theta.squaredNorm(); // squares compared: a square root only where the limit binds
    if (angle2 > limit_rad * limit_rad) {
        // Full mobilisation: the spring slips to the limit angle; no damping.
        theta *= limit_rad / std::sqrt(angle2);
        return {-k_r * theta, theta};
    }
    Vec3 torque = -k_r * theta;
    if (p.damping_ratio > 0.0) torque -= 2.0 * p.damping_ratio * std::sqrt(rolling_inertia_kg_m2 * k_r) * rolling;
    const double m2 = torque.squaredNorm();
    if (m2 > m_max * m_max) torque *= m_max / std::sqrt(m2);
    return {torque, theta};
}

/// I_r of two spheres rolling on each other: 1/I_r = Σ 1/(I + m r²), each
/// sphere's inertia about the contact point (Ai et al. 2011); a wall (or a
/// body that does not turn) adds nothing to the sum.
/// @param inertia_about_contact_first_kg_m2   I + m r² of the first body [kg·m²]
/// @param inertia_about_contact_second_kg_m2  of the second; ∞ for a wall
[[nodiscard]] inline double rolling_inertia_kg_m2(double inertia_about_contact_first_kg_m2,
    double inertia_about_contact_second_kg_m2) noexcept
{
    return 1.0 / (1.0 / inertia_about_contact_first_kg_m2 + 1.0 / inertia_about_contact_second_kg_m2);
}

} // namespace wiredem::engine
