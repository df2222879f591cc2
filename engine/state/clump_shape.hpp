// The shape of a rigid multi-sphere grain (a clump): its spheres, and the
// mass properties of their union (volume, centre of mass, inertia tensor),
// computed once per template and scaled with the grain's size. Pure
// geometry: no World, no state. docs/model.md, "Clumps".
//
// Method (union_mass_properties): the union of spheres 0 … n−1 is the
// disjoint union of the parts of each sphere i outside spheres 0 … i−1.
// Sphere i's part is integrated in spherical coordinates about its centre:
// along each ray the points inside an earlier sphere form one interval of
// the radius (a quadratic's roots), so the radial integrals of r², r³ and r⁴
// (volume, first and second moments) over what is left are exact
// polynomials; the directions are a product rule, Gauss–Legendre in cos θ
// and the trapezoidal rule in φ (n × 2n rays). The radial limits are not
// smooth in the direction where a ray grazes an earlier sphere or crosses
// the intersection circle, so each sphere's polar axis points at the earlier
// sphere that cuts deepest into it and cos θ is split at those two angles of
// that sphere: a lone sphere and a pair are then integrated to rounding
// (against the closed form of two overlapping equal spheres, d = 0.4, 1 and
// 1.6 R: relative errors ≤ 2·10⁻¹⁰ at the default n = 192; 5·10⁻⁹ at
// n = 96). Cuts by further spheres are not aligned with the grid and
// converge as about n⁻²: the built-in templates at n = 192 differ from
// n = 768 by at most 1.6·10⁻⁶ (flat; tetrahedral 1.6·10⁻⁶, crushed
// 1.7·10⁻⁷, elongated 4·10⁻¹⁰) in volume and every principal moment,
// 1.6·10⁻⁵ at n = 96 (tests/engine/test_clumps.cpp).
#pragma once

#include "core/types.hpp"

#include <Eigen/Core>

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace wiredem::engine {

/// One sphere of a clump: centre [m] in the clump's frame and radius [m].
struct ClumpSphere {
    Vec3 centre_m = Vec3::Zero();
    double radius_m = 0.0;
};

/// The mass properties of a union of spheres per unit density, in the frame
/// its spheres are given in.
struct UnionMassProperties {
    double volume_m3 = 0.0;                             ///< V [m³]
    Vec3 centre_m = Vec3::Zero();                       ///< centre of mass (of volume) [m]
    /// Inertia tensor about the centre per unit density, ∫(|p|² 1 − p pᵀ) dV [m⁵].
    Eigen::Matrix3d inertia_m5 = Eigen::Matrix3d::Zero();
};

/// Default number of Gauss–Legendre nodes in cos θ (2n in φ) per sphere.
inline constexpr int clump_default_angular_nodes = 192;

/// Volume, centre and inertia of the union of `spheres` (at least one, each
/// radius > 0) per unit density, with n × 2n rays per sphere (method above).
[[nodiscard]] UnionMassProperties union_mass_properties(
    const std::vector<ClumpSphere>& spheres, int angular_nodes = clump_default_angular_nodes);

/// A clump in its body frame: the origin at the centre of mass and the axes
/// along the principal axes of inertia, so the inertia tensor is diagonal.
struct ClumpBody {
    std::vector<ClumpSphere> spheres;                   ///< in the body frame
    double volume_m3 = 0.0;                             ///< of the union [m³]
    /// Principal moments per unit density, ascending (I₁ ≤ I₂ ≤ I₃) [m⁵].
    Vec3 principal_inertia_m5 = Vec3::Zero();
    /// The rotation from the frame the spheres were given in to the body
    /// frame's axes: a template point p is R (p_body) + centre.
    Eigen::Matrix3d template_axes = Eigen::Matrix3d::Identity();
    Vec3 template_centre_m = Vec3::Zero();              ///< the centre of mass in the template's frame [m]

    /// Radius of the sphere of the same volume, (3V/4π)^{1/3} [m].
    [[nodiscard]] double equivalent_radius_m() const;
    /// The largest distance of a sphere's surface from the centre of mass [m].
    [[nodiscard]] double bounding_radius_m() const;
    /// The smallest sphere radius [m].
    [[nodiscard]] double smallest_radius_m() const;
};

/// The body frame of a template: union_mass_properties, then its principal
/// axes (a right-handed rotation; eigenvalues ascending) and every sphere's
/// centre in them relative to the centre of mass.
[[nodiscard]] ClumpBody clump_body(
    const std::vector<ClumpSphere>& template_spheres, int angular_nodes = clump_default_angular_nodes);

/// The same body with every length multiplied by `factor` > 0 (volume × f³,
/// moments × f⁵): the mass properties are computed once per template.
[[nodiscard]] ClumpBody scaled_clump(const ClumpBody& body, double factor);

/// clump_body of a template scaled to a volume-equivalent radius of 1 m: the
/// shape a grain of radius r takes as scaled_clump(shape, r) (the
/// preparation's grain_shape).
[[nodiscard]] ClumpBody unit_clump_shape(
    const std::vector<ClumpSphere>& template_spheres, int angular_nodes = clump_default_angular_nodes);

/// A uniformly distributed random orientation from three uniform numbers in
/// [0, 1) (Shoemake, "Uniform random rotations", Graphics Gems III, 1992).
[[nodiscard]] Quat uniform_orientation(double u1, double u2, double u3);

/// The built-in templates' names: "elongated", "flat", "tetrahedral", "crushed".
inline constexpr std::array<std::string_view, 4> builtin_clump_names{"elongated", "flat", "tetrahedral", "crushed"};

/// A built-in template's spheres (in units of its largest sphere's radius),
/// or nothing for another name.
///  * elongated: three equal spheres on a line, 1.1 r apart (4.2 r × 2 r);
///  * flat: four equal spheres on a square of side 1.5 r in a plane (3.5 r × 3.5 r × 2 r);
///  * tetrahedral: four equal spheres on a regular tetrahedron of edge 1.5 r;
///  * crushed: five spheres of radii 1, 0.8, 0.7, 0.65 and 0.6 r set round
///    the first without symmetry: an angular grain with three distinct
///    principal moments (axis ratios about 1 : 0.8 : 0.65).
[[nodiscard]] std::optional<std::vector<ClumpSphere>> builtin_clump_template(std::string_view name);

} // namespace wiredem::engine
