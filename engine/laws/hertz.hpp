// Damped Hertz normal contact (the model spec §3) and the material algebra
// around it. Pure functions: numbers in, numbers out.
#pragma once

#include <algorithm>
#include <cmath>

namespace wiredem::engine {

/// Prefactor (4/3) E* √R* of the Hertz law [N/m^{3/2}]: fixed for a contact,
/// so the contact list computes it once per contact at its rebuild.
[[nodiscard]] inline double hertz_prefactor(double eff_modulus_pa, double eff_radius_m) noexcept
{
    return (4.0 / 3.0) * eff_modulus_pa * std::sqrt(eff_radius_m);
}

/// Damped Hertz normal force from the prefactor k = (4/3) E* √R*. Never attractive.
///   F_n = k ( ξ^{3/2} + γ_n √ξ dξ/dt ),  F_n ≥ 0
/// @param prefactor             hertz_prefactor(E*, R*) [N/m^{3/2}]
/// @param overlap_m             ξ > 0 [m]
/// @param overlap_rate_m_per_s  dξ/dt, positive while approaching [m/s]
/// @param damping_s             γ_n [s] (seconds, not 1/s: the model spec §3)
/// @return force magnitude along the normal [N], ≥ 0
[[nodiscard, gnu::always_inline]] inline double damped_hertz_force_n(
    double prefactor, double overlap_m, double overlap_rate_m_per_s, double damping_s) noexcept
{
    // factored as √ξ (ξ + γ ξ̇)
    const double f = prefactor * std::sqrt(overlap_m) * (overlap_m + damping_s * overlap_rate_m_per_s);
    return std::max(f, 0.0); // fast separation would make damping pull; clamp
}

/// Damped Hertz normal force. Never attractive.
///   F_n = (4/3) E* √R* ( ξ^{3/2} + γ_n √ξ dξ/dt ),  F_n ≥ 0
/// @param overlap_m             ξ > 0 [m]
/// @param overlap_rate_m_per_s  dξ/dt, positive while approaching [m/s]
/// @param eff_modulus_pa        E* [Pa]
/// @param eff_radius_m          R* [m]
/// @param damping_s             γ_n [s] (seconds, not 1/s: the model spec §3)
/// @return force magnitude along the normal [N], ≥ 0
[[nodiscard]] inline double hertz_normal_force_n(double overlap_m, double overlap_rate_m_per_s,
    double eff_modulus_pa, double eff_radius_m, double damping_s) noexcept
{
    return damped_hertz_force_n(
        hertz_prefactor(eff_modulus_pa, eff_radius_m), overlap_m, overlap_rate_m_per_s, damping_s);
}

/// Effective modulus E* of two bodies: 1/E* = (1−ν_i²)/E_i + (1−ν_j²)/E_j [Pa].
[[nodiscard]] inline double effective_modulus_pa(
    double modulus_i_pa, double poisson_i, double modulus_j_pa, double poisson_j) noexcept
{
    return 1.0 / ((1.0 - poisson_i * poisson_i) / modulus_i_pa + (1.0 - poisson_j * poisson_j) / modulus_j_pa);
}

/// Effective radius R*: 1/R* = 1/R_i + 1/R_j [m]. Pass +infinity for a wall.
[[nodiscard]] inline double effective_radius_m(double radius_i_m, double radius_j_m) noexcept
{
    if (std::isinf(radius_j_m)) return radius_i_m;
    if (std::isinf(radius_i_m)) return radius_j_m;
    return radius_i_m * radius_j_m / (radius_i_m + radius_j_m);
}

/// Tangent stiffness dF/dξ of the undamped Hertz law at overlap ξ:
/// 2 E* √(R* ξ) [N/m]. Used for time-step estimates.
[[nodiscard]] inline double hertz_stiffness_n_per_m(double overlap_m, double eff_modulus_pa, double eff_radius_m) noexcept
{
    return 2.0 * eff_modulus_pa * std::sqrt(eff_radius_m * overlap_m);
}

/// Maximum overlap of an undamped Hertz collision of reduced mass m* at
/// impact speed v: ξ_max = (15 m* v² / (16 E* √R*))^{2/5} [m].
[[nodiscard]] inline double hertz_max_overlap_m(double reduced_mass_kg, double impact_speed_m_per_s,
    double eff_modulus_pa, double eff_radius_m) noexcept
{
    return std::pow(15.0 * reduced_mass_kg * impact_speed_m_per_s * impact_speed_m_per_s
                        / (16.0 * eff_modulus_pa * std::sqrt(eff_radius_m)),
        0.4);
}

/// Duration of an undamped Hertz collision: t_c = 2 I ξ_max / v with
/// I = ∫₀¹ dx/√(1 − x^{5/2}) = (2/5) B(2/5, 1/2) ≈ 1.4716 [s].
[[nodiscard]] inline double hertz_contact_time_s(double reduced_mass_kg, double impact_speed_m_per_s,
    double eff_modulus_pa, double eff_radius_m) noexcept
{
    const double integral = 0.4 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
    return 2.0 * integral
         * hertz_max_overlap_m(reduced_mass_kg, impact_speed_m_per_s, eff_modulus_pa, eff_radius_m)
         / impact_speed_m_per_s;
}

/// Coefficient of normal restitution of a head-on damped Hertz collision,
/// obtained by integrating the one-dimensional equation of motion
/// m* ξ̈ = −F_n(ξ, ξ̇) from ξ = 0, ξ̇ = v with a fine RK4 step until the force
/// vanishes (the clamp F_n ≥ 0 ends the contact) or ξ returns to 0.
/// @return v_out / v_in, in [0, 1]
[[nodiscard]] double hertz_restitution(double reduced_mass_kg, double impact_speed_m_per_s,
    double eff_modulus_pa, double eff_radius_m, double damping_s);

/// The damping time γ_n [s] that gives restitution `restitution` (0 < e ≤ 1)
/// for a head-on collision of the given pair at the given speed (bisection on
/// hertz_restitution; e is monotone in γ_n). For this law e depends weakly on
/// the impact speed (≈ v^{1/10}), so the reference speed is part of the answer.
[[nodiscard]] double hertz_damping_for_restitution_s(double restitution, double reduced_mass_kg,
    double impact_speed_m_per_s, double eff_modulus_pa, double eff_radius_m);

} // namespace wiredem::engine
