// Turning an orientation by one step's rotation vector, shared by both integrators.
#pragma once

#include "core/types.hpp"

#include <cmath>
#include <cstddef>

namespace wiredem::engine {

/// The unit quaternion exp(½ θ) of a rotation vector θ (angle |θ| about θ̂):
/// (cos(|θ|/2), sin(|θ|/2) θ̂). A grain turns by ω δt ≪ 1 rad per step, so
/// below |θ| = 10⁻² the cosine and sin(|θ|/2)/|θ| come from their Taylor
/// series to the θ⁴ term, whose remainder (≤ |θ|⁶/46080 ≈ 2·10⁻¹⁷) is below
/// one ulp of 1; this spares a sincos per grain and step.
[[nodiscard]] inline Quat rotation_quaternion(const Vec3& theta) noexcept
{
    const double a2 = theta.squaredNorm();
    double c, s_over_angle;
    if (a2 < 1e-4) {
        c = 1.0 - a2 / 8.0 + a2 * a2 / 384.0;
        s_over_angle = 0.5 - a2 / 48.0 + a2 * a2 / 3840.0;
    } else {
        const double a = std::sqrt(a2);
        c = std::cos(0.5 * a);
        s_over_angle = std::sin(0.5 * a) / a;
    }
    return Quat(c, s_over_angle * theta.x(), s_over_angle * theta.y(), s_over_angle * theta.z());
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
