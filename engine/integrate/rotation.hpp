// Turning an orientation by one step's rotation vector, shared by both integrators.
#pragma once

#include "core/types.hpp"

#include <cmath>
#include <cstddef>

namespace wiredem::engine {

/// cos(|θ|/2) and sin(|θ|/2)/|θ| of a turn by the angle |θ| = √a2 [rad²].
/// A grain turns by ω δt ≪ 1 rad per step, so below |θ| = 10⁻² both come
/// from their Taylor series to the θ⁴ term, whose remainder
/// (≤ |θ|⁶/46080 ≈ 2·10⁻¹⁷) is below one ulp of 1; this spares a sincos per
/// grain and step. (Verlet's clump drift takes it for its turns about one
/// body axis, a2 = θ_k².)
struct HalfAngle {
    double cos_half;            ///< cos(|θ|/2)
    double sin_half_over_angle; ///< sin(|θ|/2)/|θ| [1/rad]
};
[[nodiscard]] inline HalfAngle half_angle(double a2) noexcept
{
    if (a2 < 1e-4) return {1.0 - a2 / 8.0 + a2 * a2 / 384.0, 0.5 - a2 / 48.0 + a2 * a2 / 3840.0};
    const double a = std::sqrt(a2);
    return {std::cos(0.5 * a), std::sin(0.5 * a) / a};
}

/// The unit quaternion exp(½ θ) of a rotation vector θ (angle |θ| about θ̂):
/// (cos(|θ|/2), sin(|θ|/2) θ̂), from half_angle.
[[nodiscard]] inline Quat rotation_quaternion(const Vec3& theta) noexcept
{
    const HalfAngle h = half_angle(theta.squaredNorm());
    const double s_over_angle = h.sin_half_over_angle;
    return Quat(h.cos_half, s_over_angle * theta.x(), s_over_angle * theta.y(), s_over_angle * theta.z());
}

/// q ← exp(½ θ) ⊗ q, renormalised.
inline void turn(Quat& q, const Vec3& theta) noexcept
{
    if (theta.x() == 0.0 && theta.y() == 0.0 && theta.z() == 0.0) return;
    q = (rotation_quaternion(theta) * q).normalized();
}

/// turn(q[i], theta[i]) for i in [0, n): eight at a time with AVX-512, four
/// with AVX2, where the CPU has them (integrate/rotation_simd.cpp; same
/// bits), else one by one.
void turn_all(Quat* q, const Vec3* theta, std::size_t n);

} // namespace wiredem::engine
