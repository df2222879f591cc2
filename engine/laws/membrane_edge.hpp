// The spring on a membrane edge (the model spec §3, with the edge law of
// state/membrane.hpp), as pure functions shared by the force stage and the
// energy account.
#pragma once

#include "core/types.hpp"
#include "state/membrane.hpp"

#include <numbers>

namespace wiredem::engine {

/// Stiffness of an edge of the triangular mesh, k_m = (√3/2) E_m d: a sheet
/// of thickness d carried by equilateral triangles [N/m].
[[nodiscard]] inline double membrane_edge_stiffness_n_per_m(double modulus_pa, double thickness_m) noexcept
{
    return std::numbers::sqrt3 / 2.0 * modulus_pa * thickness_m;
}

/// Force of the edge on node a, k (|b − a| − l₀) x̂_ab, or zero when a
/// tension-only edge is not stretched [N] (node b receives the opposite).
[[nodiscard]] inline Vec3 membrane_edge_force_n(const Vec3& a_m, const Vec3& b_m, double rest_length_m,
    double stiffness_n_per_m, MembraneEdgeLaw law) noexcept
{
    const Vec3 d = b_m - a_m;
    const double len = d.norm();
    const double stretch_m = len - rest_length_m;
    if (len == 0.0 || (law == MembraneEdgeLaw::tension_only && stretch_m <= 0.0)) return Vec3::Zero();
    return stiffness_n_per_m * stretch_m / len * d;
}

/// Energy stored in the edge, ½ k (|b − a| − l₀)², zero for a slack
/// tension-only edge [J].
[[nodiscard]] inline double membrane_edge_energy_j(double length_m, double rest_length_m, double stiffness_n_per_m,
    MembraneEdgeLaw law) noexcept
{
    const double stretch_m = length_m - rest_length_m;
    if (law == MembraneEdgeLaw::tension_only && stretch_m <= 0.0) return 0.0;
    return 0.5 * stiffness_n_per_m * stretch_m * stretch_m;
}

} // namespace wiredem::engine
