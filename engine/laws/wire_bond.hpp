// Wire bonds (the model spec §3): linear tension springs along the chain and
// bending joints at interior nodes, as pure functions. A joint is an
// elastic–perfectly-plastic hinge, E = ½ k_rot (ζ − ζ₀)² with a rest angle ζ₀
// that yields (a documented departure from the spec's ½ k_rot ζ²,
// docs/model.md, "Wire"); with ζ_y = ∞ it is the spec's spring.
#pragma once

#include "core/types.hpp"

#include <array>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>

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

/// Rest angle ζ₀ of an elastic–perfectly-plastic joint after a step that bent
/// it to ζ (docs/model.md, "Wire": the joint's moment k_rot (ζ − ζ₀) never
/// exceeds the yield moment M_y = k_rot ζ_y). Return mapping: where
/// |ζ − ζ₀| > ζ_y, ζ₀ moves to within ζ_y of ζ; ζ₀ ≥ 0 (an angle between two
/// segments is never negative; the joint is isotropic, so the bending plane of
/// the rest state is the current one). Idempotent: a second call at the same ζ
/// changes nothing. ζ_y = ∞ keeps ζ₀ (the specification's elastic wire).
/// @param zeta_rad        current angle ζ between the two segments, [0, π]
/// @param rest_angle_rad  ζ₀ before the step, ≥ 0
/// @param yield_angle_rad ζ_y > 0, or +∞ for an elastic joint
/// @return ζ₀ after the step [rad]
[[nodiscard]] inline double yielded_rest_angle_rad(double zeta_rad, double rest_angle_rad, double yield_angle_rad) noexcept
{
    // clamp(ζ₀, ζ − ζ_y, ζ + ζ_y): with ζ_y = ∞ the bounds are ∓∞ and ζ₀ stays.
    return std::max(0.0, std::min(std::max(rest_angle_rad, zeta_rad - yield_angle_rad), zeta_rad + yield_angle_rad));
}

/// A segment as the joints at its two ends see it.
struct WireSegment {
    Vec3 unit = Vec3::Zero(); ///< (x_j − x_i)/|x_j − x_i|; zero for a segment of zero length
    double length_m = 0.0;    ///< |x_j − x_i| [m]
};

/// The segment from node i to node j.
[[nodiscard]] inline WireSegment wire_segment(const Vec3& x_i_m, const Vec3& x_j_m) noexcept
{
    const Vec3 d = x_j_m - x_i_m;
    const double len = d.norm();
    if (len == 0.0) return {};
    return {d / len, len};
}

/// One interior joint i between nodes i−1 and i+1 after a step.
struct WireJoint {
    std::array<Vec3, 3> force_n;  ///< on nodes i−1, i, i+1 [N]
    double rest_angle_rad;        ///< ζ₀ after the step (yielded_rest_angle_rad) [rad]
    /// ∇ζ with respect to x_{i−1}, x_i, x_{i+1} [1/m] (what a damper on ζ̇
    /// needs): ∂ζ/∂x_{i+1} = −(â − cos ζ b̂)/(|b| sin ζ),
    /// ∂ζ/∂x_{i−1} = (b̂ − cos ζ â)/(|a| sin ζ), ∂ζ/∂x_i = −(the two); each of
    /// length 1/|b|, 1/|a|. Zero below sin ζ = wire_gradient_sin and for a
    /// segment of zero length, where the bending direction is undefined.
    std::array<Vec3, 3> angle_gradient_per_m;
};

/// The arctangent polynomial of bend_angle_rad: atan r = r + r u P(u), u = r²,
/// for |r| ≤ tan(π/8). P interpolates (atan √u − √u)/(u √u) at the 11
/// Chebyshev nodes of [0, tan²(π/8)] in 50-digit arithmetic, its coefficients
/// rounded to double (scripts/fit_bend_angle.py, which also checks the
/// result): the fit is within 5·10⁻¹⁸ of atan r, relative.
inline constexpr std::array<double, 11> bend_angle_polynomial{
    -0.3333333333333333,
    0.1999999999999552,
    -0.14285714284666542,
    0.11111111015256361,
    -0.09090904578123903,
    0.07692183190826087,
    -0.06664511447381948,
    0.0585814891280221,
    -0.0508544973794026,
    0.03923165829558719,
    -0.01917688711906226,
};

/// tan(π/8), rounded: above it, bend_angle_rad reduces its argument by π/4.
inline constexpr double bend_angle_tan_pi_8 = 0.41421356237309503;

/// The bend angle ζ = atan2(sin ζ, cos ζ) ∈ [0, π] of a joint, from
/// sin ζ = |â × b̂| ≥ 0 and cos ζ = â · b̂ (not both zero; NaN in, NaN out).
/// Not std::atan2, for speed: this is a handful of multiplications and one
/// division that the SIMD kernels (forces/wire_lanes.inc) do four or eight
/// joints at a time with the same operations, hence the same bits, where
/// std::atan2 ran one lane at a time (~6 % of a step of the paper-size cell).
/// Within 2.4 ulp of the exact arctangent (std::atan2: 0.5 ulp), a relative
/// error below 6·10⁻¹⁶; measured against 50-digit arithmetic over 200 000
/// angles (scripts/fit_bend_angle.py), and tested against std::atan2.
///
/// The reduction: t = min(s, |c|)/max(s, |c|) ∈ [0, 1]; above tan(π/8),
/// atan t = π/4 + atan((t − 1)/(t + 1)); then π/2 − a where s > |c|, and
/// π − a where c < 0.
[[nodiscard]] inline double bend_angle_rad(double sin_z, double cos_z) noexcept
{
    const double ax = cos_z < 0.0 ? -cos_z : cos_z;
    const bool steep = sin_z > ax;
    const double big = steep ? sin_z : ax;
    const double small = steep ? ax : sin_z;
    const bool reduced = small > bend_angle_tan_pi_8 * big;
    const double r = (reduced ? small - big : small) / (reduced ? small + big : big);
    const double u = r * r;
    double p = bend_angle_polynomial.back();
    for (std::size_t j = bend_angle_polynomial.size() - 1; j-- > 0;) p = p * u + bend_angle_polynomial[j];
    double a = r + (r * u) * p;
    if (reduced) a = std::numbers::pi / 4 + a;
    if (steep) a = std::numbers::pi / 2 - a;
    return cos_z < 0.0 ? std::numbers::pi - a : a;
}

/// Below this sin ζ the bending direction is taken as undefined (see wire_joint).
inline constexpr double wire_straight_sin = 1e-6;
/// Below this sin ζ a joint's ∇ζ is taken as zero (WireJoint::angle_gradient_per_m).
inline constexpr double wire_gradient_sin = 1e-9;

/// Elastic–perfectly-plastic bending joint at an interior node i: first the
/// rest angle yields (yielded_rest_angle_rad), then the forces are the exact
/// negative gradient of E = ½ k_rot (ζ − ζ₀)², ζ the angle between the
/// segments a = x_i − x_{i−1} and b = x_{i+1} − x_i. With
/// ∂ζ/∂x_{i+1} = −(â − cos ζ b̂)/(|b| sin ζ) and ∂ζ/∂x_{i−1} = (b̂ − cos ζ â)/(|a| sin ζ),
///   F_{i+1} = k (ζ − ζ₀)/sin ζ · (â − cos ζ b̂)/|b|,
///   F_{i−1} = −k (ζ − ζ₀)/sin ζ · (b̂ − cos ζ â)/|a|,   F_i = −F_{i−1} − F_{i+1};
/// they sum to zero and exert no net torque (E is invariant under translations
/// and rotations). |F_{i+1}| = k |ζ − ζ₀| / |b|: bounded.
///
/// Near sin ζ = 0. For ζ₀ = 0, ζ/sin ζ → 1 (its series below sin ζ = 10⁻⁶): the
/// straight chain feels nothing, exactly the specification's spring. For
/// ζ₀ > 0, E has a cone point at ζ = 0 (E = ½ k ζ₀² falls off linearly in every
/// bending direction: the straight joint of a formed wire is an unstable
/// equilibrium) and ∇ζ has no direction there. The ζ₀ part of the factor is
/// then taken as ζ₀ / max(sin ζ, 10⁻⁶): exact above sin ζ = 10⁻⁶, below it the
/// force falls linearly to zero at ζ = 0 (never more than k ζ₀/|b|), so it is
/// finite and continuous; the same holds at a joint folded back to ζ = π.
/// @param a, b                  segments i−1 → i and i → i+1 (wire_segment)
/// @param bending_stiffness_n_m k_rot [N·m]
/// @param rest_angle_rad        ζ₀ before the step, ≥ 0 [rad]
/// @param yield_angle_rad       ζ_y > 0, +∞ for an elastic joint [rad]
[[nodiscard]] inline WireJoint wire_joint(const WireSegment& a, const WireSegment& b, double bending_stiffness_n_m,
    double rest_angle_rad, double yield_angle_rad) noexcept
{
    const std::array<Vec3, 3> none{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    const double la = a.length_m, lb = b.length_m;
    if (la == 0.0 || lb == 0.0) return {none, rest_angle_rad, none};
    const Vec3& ua = a.unit;
    const Vec3& ub = b.unit;
    const double cos_z = ua.dot(ub);
    const double sin_z = ua.cross(ub).norm();
    const double zeta = bend_angle_rad(sin_z, cos_z);
    const double rest = yielded_rest_angle_rad(zeta, rest_angle_rad, yield_angle_rad);
    // (ζ − ζ₀)/sin ζ = ζ/sin ζ − ζ₀/sin ζ: the first with its series near the
    // straight chain, the second regularised (see above).
    const double z_over_sin = sin_z > wire_straight_sin ? zeta / sin_z : 1.0 + zeta * zeta / 6.0;
    const double k = bending_stiffness_n_m * (z_over_sin - rest / std::max(sin_z, wire_straight_sin));
    const Vec3 towards_next = ua - cos_z * ub; // â − cos ζ b̂
    const Vec3 towards_prev = ub - cos_z * ua; // b̂ − cos ζ â
    const Vec3 f_next = k / lb * towards_next;
    const Vec3 f_prev = -k / la * towards_prev;
    WireJoint joint{{f_prev, -(f_prev + f_next), f_next}, rest, none};
    if (!(sin_z < wire_gradient_sin)) {
        const Vec3 g_next = -towards_next / (lb * sin_z);
        const Vec3 g_prev = towards_prev / (la * sin_z);
        joint.angle_gradient_per_m = {g_prev, -(g_prev + g_next), g_next};
    }
    return joint;
}

/// wire_joint of the nodes x_{i−1}, x_i, x_{i+1} [m].
[[nodiscard]] inline WireJoint wire_joint(const Vec3& x_prev_m, const Vec3& x_m, const Vec3& x_next_m,
    double bending_stiffness_n_m, double rest_angle_rad, double yield_angle_rad) noexcept
{
    return wire_joint(wire_segment(x_prev_m, x_m), wire_segment(x_m, x_next_m), bending_stiffness_n_m, rest_angle_rad,
        yield_angle_rad);
}

/// Bending couple of an elastic joint with rest angle ζ₀ (default 0: the
/// specification's straight wire, E = ½ k_rot ζ²): wire_joint without yielding.
/// @return forces on nodes i−1, i, i+1 [N]
[[nodiscard]] inline std::array<Vec3, 3> wire_bending_forces_n(const Vec3& x_prev_m, const Vec3& x_m,
    const Vec3& x_next_m, double bending_stiffness_n_m, double rest_angle_rad = 0.0) noexcept
{
    return wire_joint(x_prev_m, x_m, x_next_m, bending_stiffness_n_m, rest_angle_rad,
        std::numeric_limits<double>::infinity()).force_n;
}

/// Yield angle of a joint, ζ_y = M_y / k_rot = ε_y l_w / r_w: the yield moment
/// of a round section at its elastic limit, M_y = σ_y π r_w³/4, over
/// k_rot = E_w π r_w⁴/(4 l_w), with ε_y = σ_y/E_w (the bending strain at a
/// joint is r_w ζ / l_w). +∞ (elastic) for ε_y = +∞ [rad].
[[nodiscard]] inline double wire_bending_yield_angle_rad(double yield_strain, double radius_m, double segment_m) noexcept
{
    return yield_strain * segment_m / radius_m;
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
