// The per-step orientation update against Eigen's angle–axis quaternion.
#include "integrate/rotation.hpp"

#include <gtest/gtest.h>

using namespace wiredem::engine;

TEST(Rotation, QuaternionOfARotationVectorMatchesAngleAxisOnBothSidesOfTheSeriesBranch)
{
    const Vec3 axis = Vec3(0.3, -0.5, 0.8).normalized();
    for (double angle : {1e-9, 1e-5, 3e-3, 9.99e-3, 1.001e-2, 0.3, 2.5}) {
        const Quat q = rotation_quaternion(angle * axis);
        const Quat ref(Eigen::AngleAxisd(angle, axis));
        EXPECT_NEAR(q.w(), ref.w(), 2e-16) << angle;
        EXPECT_NEAR((q.vec() - ref.vec()).norm(), 0.0, 2e-16 * std::max(1.0, angle)) << angle;
        EXPECT_NEAR(q.norm(), 1.0, 4e-16) << angle;
    }
}

TEST(Rotation, ManySmallTurnsAddUpToTheWholeTurn)
{
    // 10⁶ steps of ω δt = π·10⁻⁶ about z: half a turn.
    Quat q = Quat::Identity();
    const Vec3 step(0.0, 0.0, std::numbers::pi * 1e-6);
    for (int i = 0; i < 1000000; ++i) turn(q, step);
    const Vec3 x = q * Vec3::UnitX();
    EXPECT_NEAR(x.x(), -1.0, 1e-9);
    EXPECT_NEAR(x.y(), 0.0, 1e-9);
}
