// Geometry adapters of the contact pipeline: for one contact (a body pair, or
// a body against a plane or the inside of a cylinder), the normal, overlap,
// lever arms and relative velocity that the one contact kernel
// (compute_contact_forces, engine/step.cpp) turns into forces with the laws
// of laws/. Pure functions of positions and velocities.
#pragma once

#include "core/types.hpp"
#include "state/world.hpp"

#include <cmath>

namespace wiredem::engine {

/// A touching contact as the kernel sees it. `first` is a body; the normal
/// points from it towards `second` (a body or a wall).
struct ContactGeometry {
    Vec3 normal;                 ///< unit normal from first towards second
    double overlap_m = 0.0;      ///< ξ > 0 [m]
    double arm_first_m = 0.0;    ///< centre of first to the contact point [m]
    double arm_second_m = 0.0;   ///< centre of second to the contact point (0 for a wall) [m]
    Vec3 velocity_m_per_s;       ///< velocity of first's contact point relative to second's [m/s]
};

/// Signed distance from a body's centre to a wall (positive inside the
/// domain) and the unit normal from the body towards the wall.
struct WallGap {
    double gap_m;
    Vec3 towards;
};
[[nodiscard]] inline WallGap wall_gap(const Wall& wall, const Vec3& x)
{
    if (wall.shape == Wall::Shape::plane) return {(x - wall.point_m).dot(wall.normal), -wall.normal};
    Vec3 radial = x - wall.point_m;
    radial.z() = 0.0;
    const double rho = radial.norm();
    return {wall.radius_m - rho, rho > 0.0 ? Vec3(radial / rho) : Vec3(Vec3::UnitX())};
}

/// Two spheres a and b; velocities and spins are the scaled derivatives
/// δt v and δt ω. False when they do not overlap (or coincide).
[[nodiscard, gnu::always_inline]] inline bool sphere_sphere_geometry(const Vec3& x_a, const Vec3& x_b, double r_a,
    double r_b, const Vec3& v_dt_a, const Vec3& v_dt_b, const Vec3& spin_dt_a, const Vec3& spin_dt_b, double inv_dt,
    ContactGeometry& g)
{
    const Vec3 d = x_b - x_a;
    const double dist2 = d.squaredNorm();
    if (dist2 >= (r_a + r_b) * (r_a + r_b) || dist2 == 0.0) return false;
    const double dist = std::sqrt(dist2);
    g.overlap_m = r_a + r_b - dist;
    g.normal = d * (1.0 / dist);
    g.arm_first_m = r_a - 0.5 * g.overlap_m;
    g.arm_second_m = r_b - 0.5 * g.overlap_m;
    g.velocity_m_per_s = ((v_dt_a - v_dt_b) + (g.arm_first_m * spin_dt_a + g.arm_second_m * spin_dt_b).cross(g.normal))
                       * inv_dt;
    return true;
}

/// A sphere against a wall moving with its prescribed velocity. False when
/// they do not overlap.
[[nodiscard, gnu::always_inline]] inline bool sphere_wall_geometry(const Wall& wall, const Vec3& x, double r,
    const Vec3& v_dt, const Vec3& spin_dt, double inv_dt, ContactGeometry& g)
{
    const auto [gap, towards] = wall_gap(wall, x);
    if (r - gap <= 0.0) return false;
    g.overlap_m = r - gap;
    g.normal = towards;
    g.arm_first_m = r - 0.5 * g.overlap_m;
    g.arm_second_m = 0.0;
    g.velocity_m_per_s = v_dt * inv_dt + g.arm_first_m * Vec3(spin_dt * inv_dt).cross(towards) - wall.velocity_m_per_s;
    return true;
}

} // namespace wiredem::engine
