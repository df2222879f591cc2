#include "specimen/pattern.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>

namespace wiredem::engine {

bool parse_pattern_kind(std::string_view name, PatternKind& out)
{
    const std::optional<PatternKind> k = value_named(pattern_kind_names, name);
    if (k) out = *k;
    return k.has_value();
}

std::string_view pattern_name(PatternKind kind) { return to_string(kind); }

double pattern_reach_m(const PatternSpec& p)
{
    switch (p.pattern) {
    case PatternKind::none: return 0.0;
    case PatternKind::spiral_helix: return p.helix_radius_m + p.inner_radius_m;
    case PatternKind::toolpath: {
        // A leg between two points stays within the larger of their radii,
        // and turning a layer about the axis keeps every radius.
        double reach = 0.0;
        for (const Vec3& x : p.toolpath_m) reach = std::max(reach, std::hypot(x.x(), x.y()));
        return reach;
    }
    default: return p.helix_radius_m;
    }
}

namespace {

/// (x, y) of `x` turned about the z axis by `angle_rad`, z = 0.
Vec3 turned(const Vec3& x, double angle_rad)
{
    const double c = std::cos(angle_rad), s = std::sin(angle_rad);
    return {c * x.x() - s * x.y(), s * x.x() + c * x.y(), 0.0};
}

} // namespace

NozzlePath::NozzlePath(const PatternSpec& spec, double hairpin_gap_m) : spec_(spec), hairpin_gap_m_(hairpin_gap_m)
{
    if (spec_.pattern != PatternKind::toolpath) return;
    std::vector<Vec3>& points = spec_.toolpath_m;
    for (Vec3& x : points) x.z() = 0.0;
    // Legs: point i to point i + 1, and the last point to the next layer's first.
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3 to = i + 1 < points.size() ? points[i + 1] : turned(points[0], spec_.toolpath_rotation_per_layer_rad);
        leg_start_m_.push_back(layer_m_);
        leg_m_.push_back((to - points[i]).norm());
        layer_m_ += leg_m_.back();
    }
}

Vec3 NozzlePath::toolpath_at(double s_m) const
{
    const std::vector<Vec3>& points = spec_.toolpath_m;
    if (!(layer_m_ > 0.0)) return points.empty() ? Vec3::Zero() : points[0];
    const double layer = std::floor(s_m / layer_m_);
    const double u = s_m - layer * layer_m_;
    // The leg that holds u: the last one starting at or before it (a leg of
    // zero length is never the last such).
    const auto next = std::upper_bound(leg_start_m_.begin(), leg_start_m_.end(), u);
    const auto i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(next - leg_start_m_.begin() - 1, 0));
    const Vec3& from = points[i];
    const Vec3 to = i + 1 < points.size() ? points[i + 1] : turned(points[0], spec_.toolpath_rotation_per_layer_rad);
    const double t = leg_m_[i] > 0.0 ? std::min(1.0, (u - leg_start_m_[i]) / leg_m_[i]) : 0.0;
    return turned(from + t * (to - from), layer * spec_.toolpath_rotation_per_layer_rad);
}

NozzlePath::Hairpin NozzlePath::hairpin() const
{
    const double ra = spec_.helix_radius_m, gap = hairpin_gap_m_;
    Hairpin h;
    // Hairpins φ_rs apart must not touch near the axis: their tips are
    // 2 r_min sin(φ_rs/2) apart, which must exceed two gaps.
    const double half = 0.5 * std::min(spec_.period_angle_rad, std::numbers::pi);
    h.r_min_m = std::max(gap, 2.0 * gap / (2.0 * std::sin(half)));
    h.in_m = ra - h.r_min_m;
    h.out_m = std::sqrt(ra * ra - gap * gap) - h.r_min_m;
    h.beta_rad = std::asin(gap / ra);
    h.period_m = h.in_m + gap + h.out_m + (spec_.period_angle_rad + h.beta_rad) * ra;
    return h;
}

Vec3 NozzlePath::spiral_point(double theta) const
{
    // The small circle turns once for every φ_rs of the large angle.
    const double psi = 2.0 * std::numbers::pi * theta / spec_.period_angle_rad;
    return {spec_.helix_radius_m * std::cos(theta) + spec_.inner_radius_m * std::cos(psi),
        spec_.helix_radius_m * std::sin(theta) + spec_.inner_radius_m * std::sin(psi), 0.0};
}

double NozzlePath::spiral_speed(double theta) const
{
    const double k = 2.0 * std::numbers::pi / spec_.period_angle_rad;
    const double psi = k * theta;
    const double dx = -spec_.helix_radius_m * std::sin(theta) - spec_.inner_radius_m * k * std::sin(psi);
    const double dy = spec_.helix_radius_m * std::cos(theta) + spec_.inner_radius_m * k * std::cos(psi);
    return std::hypot(dx, dy);
}

double NozzlePath::spiral_angle(double s_m) const
{
    if (s_m < cached_s_) cached_s_ = 0.0, cached_theta_ = 0.0;
    // Steps of at most 20 µm of path: RK4 error far below a nanometre.
    double s = cached_s_, theta = cached_theta_;
    while (s < s_m) {
        const double h = std::min(20e-6, s_m - s);
        auto f = [&](double th) { return 1.0 / spiral_speed(th); };
        const double k1 = f(theta), k2 = f(theta + 0.5 * h * k1), k3 = f(theta + 0.5 * h * k2), k4 = f(theta + h * k3);
        theta += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
        s += h;
    }
    cached_s_ = s;
    cached_theta_ = theta;
    return theta;
}

Vec3 NozzlePath::at(double s_m) const
{
    const double ra = spec_.helix_radius_m;
    switch (spec_.pattern) {
    case PatternKind::none:
        return Vec3::Zero();
    case PatternKind::toolpath:
        return toolpath_at(s_m);
    case PatternKind::helix:
        return {ra * std::cos(s_m / ra), ra * std::sin(s_m / ra), 0.0};
    case PatternKind::spiral_helix:
        return spiral_point(spiral_angle(s_m));
    case PatternKind::radial_helix: {
        // A period starts with a hairpin excursion along the direction θₙ = n φ_rs:
        // in along the radius to r_min, across by the hairpin gap, back out on
        // the parallel line until it meets the circle again (at θₙ − β,
        // sin β = gap/R_a), then along the circle to θₙ₊₁. Excursions are φ_rs apart.
        const Hairpin h = hairpin();
        const double n = std::floor(s_m / h.period_m);
        double u = s_m - n * h.period_m;
        const double th = n * spec_.period_angle_rad;
        const Vec3 radial(std::cos(th), std::sin(th), 0.0), side(-std::sin(th), std::cos(th), 0.0);
        if (u < h.in_m) return (ra - u) * radial;                                   // in
        u -= h.in_m;
        if (u < hairpin_gap_m_) return h.r_min_m * radial - u * side;              // across
        u -= hairpin_gap_m_;
        if (u < h.out_m) return (h.r_min_m + u) * radial - hairpin_gap_m_ * side;  // out
        u -= h.out_m;
        const double angle = th - h.beta_rad + u / ra;                             // along the circle
        return {ra * std::cos(angle), ra * std::sin(angle), 0.0};
    }
    }
    return Vec3::Zero();
}

} // namespace wiredem::engine
