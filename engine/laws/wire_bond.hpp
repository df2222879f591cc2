// Wire bonds (the model spec §3): linear tension springs along the chain and
// bending springs at interior nodes, as pure functions.
#pragma once

#include "core/types.hpp"

#include <array>
#include <cmath>

namespace wiredem::engine {

/// Axial spring of one segment, F = k_elo (|x_j − x_i| − l₀) x̂_ij.
/// @return force on node i [N] (node j receives the opposite)
[[nodiscard]] inline Vec3 wire_stretch_force_n(const Vec3& x_i_m, const Vec3& x_j_m, double rest_length_m,
    double stiffness_n_per_m) noexcept
{
    const Vec3 d = x_j_m - x_i_m;
    const double len = d.norm();
    if (len == 0.0) return Vec3::Zero();
    return stiffness_n_per_m * (len - rest_length_m) / len * d;
}

/// Bending couple at an interior node i between nodes i−1 and i+1: the exact
/// negative gradient of E = ½ k_rot ζ², ζ the angle between the segments
/// a = x_i − x_{i−1} and b = x_{i+1} − x_i. With ∂ζ/∂b = −(â − cos ζ b̂)/(|b| sin ζ)
/// and ∂ζ/∂a = −(b̂ − cos ζ â)/(|a| sin ζ), the forces are
///   F_{i+1} = k ζ/sin ζ · (â − cos ζ b̂)/|b|,  F_{i−1} = −k ζ/sin ζ · (b̂ − cos ζ â)/|a|,
///   F_i = −F_{i−1} − F_{i+1};
/// they sum to zero and exert no net torque (the energy is invariant under
/// translations and rotations). ζ/sin ζ → 1 for a straight chain.
/// @return forces on nodes i−1, i, i+1 [N]
[[nodiscard]] inline std::array<Vec3, 3> wire_bending_forces_n(const Vec3& x_prev_m, const Vec3& x_m,
    const Vec3& x_next_m, double bending_stiffness_n_m) noexcept
{
    const Vec3 a = x_m - x_prev_m, b = x_next_m - x_m;
    const double la = a.norm(), lb = b.norm();
    if (la == 0.0 || lb == 0.0) return {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    const Vec3 ua = a / la, ub = b / lb;
    const double cos_z = ua.dot(ub);
    const double sin_z = ua.cross(ub).norm();
    const double zeta = std::atan2(sin_z, cos_z);
    // ζ / sin ζ, with its series near the straight chain (sin ζ → 0).
    const double z_over_sin = sin_z > 1e-6 ? zeta / sin_z : 1.0 + zeta * zeta / 6.0;
    const double k = bending_stiffness_n_m * z_over_sin;
    const Vec3 f_next = k / lb * (ua - cos_z * ub);
    const Vec3 f_prev = -k / la * (ub - cos_z * ua);
    return {f_prev, -(f_prev + f_next), f_next};
}

/// Axial stiffness of a segment, k_elo = E_w π r_w² / l_w [N/m].
[[nodiscard]] inline double wire_axial_stiffness_n_per_m(double modulus_pa, double radius_m, double segment_m) noexcept
{
    return modulus_pa * M_PI * radius_m * radius_m / segment_m;
}

/// Bending stiffness, k_rot = E_w π r_w⁴ / (4 l_w) = E I / l_w [N·m].
[[nodiscard]] inline double wire_bending_stiffness_n_m(double modulus_pa, double radius_m, double segment_m) noexcept
{
    return modulus_pa * M_PI * radius_m * radius_m * radius_m * radius_m / (4.0 * segment_m);
}

} // namespace wiredem::engine
