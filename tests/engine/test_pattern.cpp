// The nozzle trajectories of the four deployment patterns.
#include "specimen/pattern.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace wiredem::engine;

namespace {

PatternSpec pattern(PatternKind kind)
{
    PatternSpec p;
    p.kind = kind;
    return p; // defaults: R_a = 12 mm, R_i = 4 mm, φ_rs = π/2
}

constexpr double ds = 20e-6; // sampling step along the path [m]

} // namespace

TEST(NozzlePath, PathSpeedIsConstantForEveryPattern)
{
    // Equal steps in path length give equal chords, up to the curvature:
    // chord/arc − 1 ≈ −ds²/(24 ρ²) < 1e-3 for every radius of curvature
    // ρ > 0.13 mm. The hairpin's corners cut chords short: 4 corners per
    // excursion (one every ≥ 35 mm of path), one chord each.
    for (PatternKind kind : {PatternKind::helix, PatternKind::spiral_helix, PatternKind::radial_helix}) {
        const NozzlePath path(pattern(kind), 1.25e-3);
        Vec3 prev = path.at(0.0);
        int off = 0;
        const int samples = 20000;
        for (int i = 1; i < samples; ++i) {
            const Vec3 x = path.at(i * ds);
            if (std::abs((x - prev).norm() / ds - 1.0) > 1e-3) ++off;
            prev = x;
        }
        const int corners = kind == PatternKind::radial_helix ? 4 * static_cast<int>(samples * ds / 35e-3 + 1) : 0;
        EXPECT_LE(off, corners) << pattern_name(kind);
    }
}

TEST(NozzlePath, StaysWithinThePatternsReach)
{
    for (PatternKind kind : {PatternKind::helix, PatternKind::spiral_helix, PatternKind::radial_helix}) {
        const PatternSpec p = pattern(kind);
        const NozzlePath path(p, 1.25e-3);
        double farthest = 0.0;
        for (int i = 0; i < 20000; ++i) farthest = std::max(farthest, path.at(i * ds).norm());
        EXPECT_LE(farthest, pattern_reach_m(p) * (1.0 + 1e-9)) << pattern_name(kind);
        EXPECT_GT(farthest, 0.99 * pattern_reach_m(p)) << pattern_name(kind);
    }
}

TEST(NozzlePath, SpiralMakesOneSmallTurnPerPeriodAngle)
{
    // Every generated point is R_i from the large circle's point at Θ, in the
    // direction ψ = 2π Θ / φ_rs: one small turn per φ_rs of the large angle.
    const PatternSpec p = pattern(PatternKind::spiral_helix);
    const NozzlePath path(p, 1.25e-3);
    double prev_theta = 0.0;
    for (int i = 1; i < 20000; ++i) {
        const double s = i * ds;
        const double theta = path.large_angle(s);
        ASSERT_GT(theta, prev_theta);
        prev_theta = theta;
        const Vec3 offset = path.at(s) - p.helix_radius_m * Vec3(std::cos(theta), std::sin(theta), 0.0);
        const double psi = 2.0 * std::numbers::pi * theta / p.period_angle_rad;
        EXPECT_NEAR(offset.norm(), p.inner_radius_m, 1e-12);
        EXPECT_NEAR(offset.x(), p.inner_radius_m * std::cos(psi), 1e-12);
        EXPECT_NEAR(offset.y(), p.inner_radius_m * std::sin(psi), 1e-12);
    }
    EXPECT_GT(prev_theta, 2.0 * p.period_angle_rad); // the walk covered several periods
}

TEST(NozzlePath, RadialExcursionsArePeriodAngleApartAndReachTowardsTheAxis)
{
    const PatternSpec p = pattern(PatternKind::radial_helix);
    const NozzlePath path(p, 1.25e-3);
    // Find the innermost point of each excursion and its angle.
    std::vector<double> tip_angles;
    double prev_r = path.at(0.0).norm(), min_r = prev_r;
    bool descending = false;
    double tip_angle = 0.0;
    for (int i = 1; i < 60000; ++i) {
        const Vec3 x = path.at(i * ds);
        const double r = x.norm();
        if (r < 0.5 * p.helix_radius_m) {
            if (!descending) min_r = r;
            descending = true;
            if (r <= min_r) min_r = r, tip_angle = std::atan2(x.y(), x.x());
        } else if (descending) {
            tip_angles.push_back(tip_angle);
            descending = false;
        }
        prev_r = r;
    }
    ASSERT_GE(tip_angles.size(), 4u);
    for (std::size_t k = 1; k < tip_angles.size(); ++k) {
        double step = tip_angles[k] - tip_angles[k - 1];
        while (step < 0) step += 2.0 * std::numbers::pi;
        EXPECT_NEAR(step, p.period_angle_rad, 0.02) << "excursion " << k;
    }
    EXPECT_LT(min_r, 0.25 * p.helix_radius_m);
}
