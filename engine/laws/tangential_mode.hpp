// The oscillation of a contact's tangential and rolling springs (issue 42
// item 4; docs/model.md, "The tangential and rolling springs in the step"):
// the stable time step (stable_time_step) and a column test's live check
// (live_limits) take it.
#pragma once

namespace wiredem::engine {

/// ω² of the tangential and rolling springs of a sticking contact, on one
/// of its bodies [1/s²]. The tangential spring of stiffness K = k_t F_n
/// acts on the slip of the contact points; a tangential force F there
/// moves the body's contact point by F (1/m + a²/I) (its centre, and its
/// rotation through the torque a F, a the lever arm r − ξ/2). The rolling
/// spring k_r = f_r K R*² turns the body by k_r/I. Both act on the same
/// rotation; the high mode of the pair stays below the sum of the two ω²
/// (the stiffness matrices add: Weyl):
///     ω² ≤ K (1/m + a²/I) + k_r/I.
/// A solid sphere (I = 0.4 m r²) on a fixed body: 3.5 K/m without rolling
/// (exact), 6 K/m with f_r = 1 on a plate (exact 5.55 K/m); two free
/// bodies: the sum of both bodies' terms (7 K/m for two equal spheres).
/// @param spring_n_per_m            K = k_t F_n [N/m]
/// @param tangential_mobility_per_kg  1/m + a²/I [1/kg] (1/m for a body that does not turn)
/// @param rolling_spring_n_m        k_r = f_r K R*² [N·m/rad] (0 without rolling)
/// @param inverse_inertia_per_kg_m2 1/I [1/(kg·m²)] (0 for a body that does not turn)
[[nodiscard]] inline double tangential_omega2(double spring_n_per_m, double tangential_mobility_per_kg,
    double rolling_spring_n_m, double inverse_inertia_per_kg_m2) noexcept
{
    return spring_n_per_m * tangential_mobility_per_kg + rolling_spring_n_m * inverse_inertia_per_kg_m2;
}

} // namespace wiredem::engine
