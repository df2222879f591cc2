// The per-step orientation update against Eigen's angle–axis quaternion.
#include "helpers.hpp"
#include "integrate/rotation.hpp"
#include "scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

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

TEST(Rotation, TheSimdTurnGivesTheScalarBits)
{
    // turn_all (eight or four grains per instruction where the CPU has the
    // SIMD paths) against turn(), one grain at a time: blocks of small turns
    // (whose θ⁴ terms the SIMD path may leave out), of turns around that
    // bound, at rest, past the series branch, and mixed.
    const std::vector<SimdKernels> choices = test::simd_choices();
    if (choices.empty()) GTEST_SKIP() << "neither AVX-512 nor AVX2 on this CPU: the scalar path is the only one";
    const test::RestoreSimdKernels restore;
    SplitMix64 rng(17);
    // |θ| where |θ|⁴/384 is half the spacing below 1, and where |θ|⁴/3840 is
    // half the spacing below ½.
    const double bound_c = std::pow(384.0 * 0x1p-54, 0.25), bound_s = std::pow(3840.0 * 0x1p-55, 0.25);
    std::vector<Vec3> theta;
    std::vector<Quat> q;
    auto add = [&](double angle) {
        const Vec3 axis = Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalized();
        theta.push_back(angle * axis);
        q.push_back(Quat(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5).normalized());
    };
    for (int block = 0; block < 400; ++block)
        for (int l = 0; l < 8; ++l) {
            const int kind = block % 6;
            if (kind == 0) add(1e-9 * std::pow(1e5, rng.uniform()));                  // small: 1e-9 … 1e-4
            else if (kind == 1) add(bound_c * (0.9 + 0.2 * rng.uniform()));           // around the bounds
            else if (kind == 5) add(bound_s * (0.9 + 0.2 * rng.uniform()));
            else if (kind == 2) add(l % 3 == 0 ? 0.0 : 1e-7);                          // some at rest
            else if (kind == 3) add(l == 5 ? 0.05 : 1e-6 * rng.uniform());            // one past the series
            else add(std::pow(10.0, -12.0 + 10.0 * rng.uniform()));                    // anything
        }
    std::vector<Quat> expected = q;
    for (std::size_t i = 0; i < q.size(); ++i) turn(expected[i], theta[i]);
    for (SimdKernels choice : choices) {
        set_simd_kernels(choice);
        std::vector<Quat> got = q;
        turn_all(got.data(), theta.data(), got.size());
        for (std::size_t i = 0; i < q.size(); ++i)
            ASSERT_EQ(std::memcmp(got[i].coeffs().data(), expected[i].coeffs().data(), 4 * sizeof(double)), 0)
                << "grain " << i << ", |θ| = " << theta[i].norm();
    }
}
