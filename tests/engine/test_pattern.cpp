// The nozzle trajectories of the four deployment patterns.
#include "specimen/pattern.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>
#include <numbers>

using namespace wiredem::engine;

namespace {

PatternSpec pattern(PatternKind kind)
{
    PatternSpec p;
    p.pattern = kind;
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

namespace {

/// A toolpath of one layer: `points` (x, y), turned by `turn_rad` per layer.
PatternSpec toolpath(std::vector<Vec3> points, double turn_rad = 0.0)
{
    PatternSpec p;
    p.pattern = PatternKind::toolpath;
    p.toolpath_m = std::move(points);
    p.toolpath_rotation_per_layer_rad = turn_rad;
    return p;
}

/// A regular n-gon inscribed in the circle of radius r, its first vertex on +x, counter-clockwise.
std::vector<Vec3> polygon(int n, double r)
{
    std::vector<Vec3> v;
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * std::numbers::pi * i / n;
        v.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
    }
    return v;
}

} // namespace

TEST(Toolpath, WalksItsPolylineAtThePathSpeedThenTurnsForTheNextLayer)
{
    // A square of side 8 mm, open at its last corner: the layer is the three
    // sides and the leg from the last corner back to the first, turned by
    // 90° for the next layer (which here is the same square, started at
    // another corner).
    const std::vector<Vec3> square{{4e-3, -4e-3, 0}, {4e-3, 4e-3, 0}, {-4e-3, 4e-3, 0}, {-4e-3, -4e-3, 0}};
    const PatternSpec p = toolpath(square, std::numbers::pi / 2);
    const NozzlePath path(p, 1.25e-3);
    const double side = 8e-3;
    // Turned by 90°, the first point (4, −4) goes to (4, 4): the closing leg from (−4, −4) is a diagonal.
    EXPECT_NEAR(path.layer_length_m(), 3 * side + std::hypot(8e-3, 8e-3), 1e-15);
    EXPECT_NEAR((path.at(0.0) - square[0]).norm(), 0.0, 1e-18);
    EXPECT_NEAR((path.at(0.5 * side) - Vec3(4e-3, 0, 0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((path.at(2.5 * side) - Vec3(-4e-3, 0, 0)).norm(), 0.0, 1e-15);
    const double layer = path.layer_length_m();
    // The second layer starts at the first point turned by 90° and follows the turned polyline.
    EXPECT_NEAR((path.at(layer) - Vec3(4e-3, 4e-3, 0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((path.at(layer + 0.5 * side) - Vec3(0, 4e-3, 0)).norm(), 0.0, 1e-15);
    // Equal steps in path length give equal chords but at the corners.
    Vec3 prev = path.at(0.0);
    int off = 0;
    for (int i = 1; i < 5000; ++i) {
        const Vec3 x = path.at(i * ds);
        if (std::abs((x - prev).norm() / ds - 1.0) > 1e-9) ++off;
        prev = x;
    }
    EXPECT_LE(off, 2 * static_cast<int>(5000 * ds / layer + 1) * 4) << "only the steps across a corner are short";
    EXPECT_DOUBLE_EQ(pattern_reach_m(p), std::hypot(4e-3, 4e-3));
    PatternKind k;
    ASSERT_TRUE(parse_pattern_kind("toolpath", k));
    EXPECT_EQ(k, PatternKind::toolpath);
}

TEST(Toolpath, StaysWithinItsReachOverManyTurnedLayers)
{
    const PatternSpec p = toolpath({{5e-3, 0, 0}, {-2e-3, 3e-3, 0}, {1e-3, -6e-3, 0}}, 0.7);
    const NozzlePath path(p, 1.25e-3);
    double farthest = 0.0;
    for (int i = 0; i < 20000; ++i) farthest = std::max(farthest, path.at(i * ds).norm());
    EXPECT_LE(farthest, pattern_reach_m(p) * (1.0 + 1e-12));
    EXPECT_GT(farthest, 0.99 * pattern_reach_m(p));
}

TEST(Toolpath, APolygonReproducesTheHelixWithinTheChordBound)
{
    // The built-in helix of R_a = 4 mm against a toolpath of its inscribed
    // regular n-gon (n = 2000, not turned): at path length s the two nozzles
    // are apart by at most the polygon's sagitta R(1 − cos(π/n)) plus the
    // lag of the polygon's arc length behind the circle's, s(1 − sin(π/n)/(π/n))
    // R-scaled: a polygon of perimeter 2nR sin(π/n) walked at the same speed
    // finishes each turn early by 2πR − 2nR sin(π/n): 4.9·10⁻⁹ m and
    // 1.03·10⁻⁸ m per turn, 1.1·10⁻⁷ m over ten turns.
    PatternSpec helix = pattern(PatternKind::helix);
    helix.helix_radius_m = 4e-3;
    const int n = 2000;
    PatternSpec gon = toolpath(polygon(n, helix.helix_radius_m));
    gon.helix_radius_m = helix.helix_radius_m; // the same path speed ω R_a
    const NozzlePath a(helix, 1.25e-3), b(gon, 1.25e-3);
    EXPECT_DOUBLE_EQ(a.speed_m_per_s(), b.speed_m_per_s());
    const double r = helix.helix_radius_m, turn = 2.0 * std::numbers::pi * r;
    const double sagitta = r * (1.0 - std::cos(std::numbers::pi / n));
    const double short_per_turn = turn - 2.0 * n * r * std::sin(std::numbers::pi / n);
    double worst = 0.0, worst_bound_ratio = 0.0;
    for (int i = 0; i <= 100000; ++i) {
        const double s = 10.0 * turn * i / 100000;
        const double apart = (a.at(s) - b.at(s)).norm();
        const double bound = sagitta + short_per_turn * (std::floor(s / turn) + 1.0);
        worst = std::max(worst, apart);
        worst_bound_ratio = std::max(worst_bound_ratio, apart / bound);
    }
    EXPECT_LE(worst_bound_ratio, 1.0) << "largest distance " << worst << " m";
    EXPECT_LT(worst, 1.1e-7);
}
