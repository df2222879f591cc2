// Least-squares Mohr–Coulomb envelope; see mohr_coulomb.hpp.
#include "analysis/mohr_coulomb.hpp"

#include "core/format.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

namespace wiredem::engine::analysis {

namespace {

std::string test_label(std::size_t i) { return "test " + std::to_string(i); }

/// Σ (t − a − b p)² over the circle tops, in input order.
double residual_sum_of_squares(const std::vector<MohrCircle>& circles, double a_pa, double b) noexcept
{
    double ss = 0.0;
    for (const MohrCircle& m : circles) {
        const double r = m.radius_pa - (a_pa + b * m.centre_pa);
        ss += r * r;
    }
    return ss;
}

/// The envelope of the line t = a + b p. `free_parameters`: how many of a and b
/// were fitted (R² only when the circles outnumber them); `ss_tot` = Σ (t − t̄)².
Result<MohrEnvelope, std::string> envelope_of(const std::vector<MohrCircle>& circles, double a_pa, double b,
    std::size_t free_parameters, double ss_tot, const char* which)
{
    if (!(std::abs(b) < 1.0))
        return Err{std::string("mohr_coulomb: slope of the line through the circle tops") + which + " tan(alpha) = "
            + format_number(b, 6) + " has magnitude >= 1; no real friction angle (sin(phi) = tan(alpha))"};
    MohrEnvelope e;
    e.intercept_pa = a_pa;
    e.slope = b;
    e.friction_angle_rad = std::asin(b);                         // sin φ = tan α
    e.cohesion_pa = a_pa / std::cos(e.friction_angle_rad);       // c = a / cos φ
    if (circles.size() > free_parameters)
        // SS_tot = 0 means every t is equal; a horizontal line then fits exactly.
        e.r_squared = ss_tot > 0.0 ? 1.0 - residual_sum_of_squares(circles, a_pa, b) / ss_tot : 1.0;
    return e;
}

std::string format_kpa(double pa) { return fixed_number(pa * 1e-3, 1) + " kPa"; }

std::string format_deg(double rad) { return fixed_number(rad * 180.0 / std::numbers::pi, 1) + " deg"; }

/// The smallest and the largest circle centre [Pa] (circles not empty).
std::pair<double, double> centre_range_pa(const std::vector<MohrCircle>& circles) noexcept
{
    double lo = circles.front().centre_pa, hi = lo;
    for (const MohrCircle& m : circles) lo = std::min(lo, m.centre_pa), hi = std::max(hi, m.centre_pa);
    return {lo, hi};
}

std::string figures(const MohrEnvelope& e) { return "phi = " + format_deg(e.friction_angle_rad) + ", c = " + format_kpa(e.cohesion_pa); }

} // namespace

const char* to_string(FitCaveat caveat) noexcept
{
    switch (caveat) {
    case FitCaveat::single_pressure: return "single_pressure";
    case FitCaveat::two_pressures: return "two_pressures";
    case FitCaveat::narrow_band: return "narrow_band";
    case FitCaveat::negative_cohesion: return "negative_cohesion";
    case FitCaveat::negative_friction_angle: return "negative_friction_angle";
    }
    return "unknown";
}

MohrEnvelope free_envelope(const MohrCoulombFit& fit) noexcept
{
    return {fit.friction_angle_rad, fit.cohesion_pa, fit.intercept_pa, fit.slope, fit.r_squared};
}

std::string describe(FitCaveat caveat, const MohrCoulombFit& fit)
{
    // The constrained fits to read instead; one figure when the best line with
    // c >= 0 and phi >= 0 is the one through the origin.
    const bool same = fit.nonnegative.intercept_pa == 0.0 && fit.nonnegative.slope == fit.cohesionless.slope;
    const std::string instead = same
        ? "; the best fit with c >= 0 and phi >= 0 is the one with c = 0: phi = " + format_deg(fit.cohesionless.friction_angle_rad)
        : "; the best fit with c >= 0 and phi >= 0: " + figures(fit.nonnegative) + ", the one with c = 0: phi = "
            + format_deg(fit.cohesionless.friction_angle_rad);
    switch (caveat) {
    case FitCaveat::single_pressure:
        return "one pressure: c = 0 was imposed and phi = " + format_deg(fit.friction_angle_rad)
             + " is that one circle's; test at least three pressures to fit c";
    case FitCaveat::two_pressures:
        return "two pressures: a line passes through any two circle tops, so the fit (" + figures(free_envelope(fit))
             + ") is exact by construction and has no R^2; test at least three pressures" + instead;
    case FitCaveat::narrow_band:
    {
        const auto [lo, hi] = centre_range_pa(fit.circles);
        return "narrow band: the circles' centres span " + format_kpa(hi - lo) + " (" + format_kpa(lo) + " to "
             + format_kpa(hi) + "), less than their distance from sigma = 0, so c is an extrapolation longer than the band it was "
               "fitted over; widen the range of pressures" + instead;
    }
    case FitCaveat::negative_cohesion:
        return "negative cohesion c = " + format_kpa(fit.cohesion_pa)
             + ": the unconstrained line through the circle tops meets sigma = 0 below zero, a tensile strength a "
               "granular column does not have; read it as c = 0 within the scatter" + instead;
    case FitCaveat::negative_friction_angle:
        return "negative friction angle phi = " + format_deg(fit.friction_angle_rad)
             + ": the circle tops fall as the pressure rises, so the data determine no envelope" + instead;
    }
    return "unknown caveat";
}

MohrCircle mohr_circle(const PeakState& peak) noexcept
{
    return {0.5 * (peak.sigma1_pa + peak.sigma3_pa), 0.5 * (peak.sigma1_pa - peak.sigma3_pa)};
}

Result<MohrCoulombFit, std::string> fit_mohr_coulomb(std::span<const PeakState> peaks)
{
    if (peaks.empty()) return Err{std::string("mohr_coulomb: no tests given")};

    MohrCoulombFit fit;
    fit.circles.reserve(peaks.size());
    for (std::size_t i = 0; i < peaks.size(); ++i) {
        const PeakState& s = peaks[i];
        if (!std::isfinite(s.sigma1_pa) || !std::isfinite(s.sigma3_pa))
            return Err{"mohr_coulomb: " + test_label(i) + " has a non-finite stress (sigma1_pa = "
                + format_number(s.sigma1_pa, 6) + ", sigma3_pa = " + format_number(s.sigma3_pa, 6) + ")"};
        if (s.sigma1_pa < s.sigma3_pa)
            return Err{"mohr_coulomb: " + test_label(i) + " has sigma1_pa = " + format_number(s.sigma1_pa, 6)
                + " below sigma3_pa = " + format_number(s.sigma3_pa, 6) + " (not a compression peak)"};
        fit.circles.push_back(mohr_circle(s));
    }

    const std::size_t n = fit.circles.size();
    const std::vector<MohrCircle>& circles = fit.circles;
    if (n == 1) {
        // One circle: the envelope through the origin tangent to it, sin φ = t/p, c = 0.
        const MohrCircle& m = circles.front();
        if (!(m.centre_pa > 0.0))
            return Err{"mohr_coulomb: single test with circle centre p = " + format_number(m.centre_pa, 6)
                + " Pa; need p > 0 to fit phi with c = 0"};
        auto e = envelope_of(circles, 0.0, m.radius_pa / m.centre_pa, 1, 0.0, "");
        if (!e.ok()) return Err{e.error()};
        fit.friction_angle_rad = e.value().friction_angle_rad;
        fit.cohesion_pa = 0.0;
        fit.intercept_pa = 0.0;
        fit.slope = e.value().slope;
        fit.cohesion_fixed_at_zero = true;
        fit.paper_top_line_angle_rad = std::atan(fit.slope); // the paper's reading of φ
        fit.nonnegative = fit.cohesionless = e.value();
        fit.caveats.push_back(FitCaveat::single_pressure);
        return fit;
    }

    bool all_same_centre = true;
    for (const MohrCircle& m : circles) all_same_centre = all_same_centre && m.centre_pa == circles.front().centre_pa;
    if (all_same_centre)
        return Err{"mohr_coulomb: all " + std::to_string(n) + " tests have the same circle centre p = "
            + format_number(circles.front().centre_pa, 6) + " Pa; the slope is undefined"};

    // Centred sums (numerically stable): slope = S_pt / S_pp, a = t̄ − slope·p̄.
    double p_mean = 0.0, t_mean = 0.0;
    for (const MohrCircle& m : circles) {
        p_mean += m.centre_pa;
        t_mean += m.radius_pa;
    }
    p_mean /= static_cast<double>(n);
    t_mean /= static_cast<double>(n);
    double s_pp = 0.0, s_pt = 0.0, s_tt = 0.0;
    for (const MohrCircle& m : circles) {
        const double dp = m.centre_pa - p_mean, dt = m.radius_pa - t_mean;
        s_pp += dp * dp;
        s_pt += dp * dt;
        s_tt += dt * dt;
    }
    const double b_free = s_pt / s_pp;
    const double a_free = t_mean - b_free * p_mean;
    auto free = envelope_of(circles, a_free, b_free, 2, s_tt, "");
    if (!free.ok()) return Err{free.error()};
    fit.friction_angle_rad = free.value().friction_angle_rad;
    fit.cohesion_pa = free.value().cohesion_pa;
    fit.intercept_pa = a_free;
    fit.slope = b_free;
    fit.r_squared = free.value().r_squared;
    fit.paper_top_line_angle_rad = std::atan(b_free); // the paper's reading of φ

    // c = 0: minimise Σ (t − b p)² over b alone, b = Σ p t / Σ p² (raw sums:
    // the line goes through the origin, not through the mean).
    double sum_pp = 0.0, sum_pt = 0.0;
    for (const MohrCircle& m : circles) {
        sum_pp += m.centre_pa * m.centre_pa;
        sum_pt += m.centre_pa * m.radius_pa;
    }
    const double b_origin = sum_pt / sum_pp; // Σ p² > 0: the centres differ
    auto origin = envelope_of(circles, 0.0, b_origin, 1, s_tt, " with c = 0");
    if (!origin.ok()) return Err{origin.error()};
    fit.cohesionless = origin.value();

    // c ≥ 0, φ ≥ 0: a convex quadratic over the quadrant a ≥ 0, b ≥ 0. Its
    // unconstrained minimum is unique (S_pp > 0); when it lies outside the
    // quadrant, the constrained minimum lies on the quadrant's edge: on a = 0
    // at b = max(0, Σ p t / Σ p²), or on b = 0 at a = max(0, t̄) (each the
    // one-dimensional least squares, clamped). The better of the two (the
    // first on a tie) is the answer.
    if (a_free >= 0.0 && b_free >= 0.0) {
        fit.nonnegative = free.value();
    } else {
        const double b_edge = std::max(0.0, b_origin), a_edge = std::max(0.0, t_mean);
        const bool on_a_zero
            = residual_sum_of_squares(circles, 0.0, b_edge) <= residual_sum_of_squares(circles, a_edge, 0.0);
        const double a = on_a_zero ? 0.0 : a_edge, b = on_a_zero ? b_edge : 0.0;
        const std::size_t free_parameters = (a > 0.0) + (b > 0.0);
        auto bounded = envelope_of(circles, a, b, free_parameters, s_tt, " with c >= 0 and phi >= 0");
        if (!bounded.ok()) return Err{bounded.error()};
        fit.nonnegative = bounded.value();
    }

    // The caveats, in the order of FitCaveat.
    const auto [p_min, p_max] = centre_range_pa(circles);
    if (n == 2) fit.caveats.push_back(FitCaveat::two_pressures); // and no R²: any line through two tops is exact
    // The intercept is extrapolated from the nearest circle to σ = 0; when
    // that is farther than the band of centres is wide, a small scatter of
    // the tops swings c by more than the band's own change of t.
    if (p_max - p_min < p_min) fit.caveats.push_back(FitCaveat::narrow_band);
    if (fit.cohesion_pa < 0.0) fit.caveats.push_back(FitCaveat::negative_cohesion);
    if (fit.friction_angle_rad < 0.0) fit.caveats.push_back(FitCaveat::negative_friction_angle);
    return fit;
}

double unconfined_strength_pa(double friction_angle_rad, double cohesion_pa) noexcept
{
    const double s = std::sin(friction_angle_rad);
    if (!std::isfinite(cohesion_pa) || !(s < 1.0)) return std::numeric_limits<double>::quiet_NaN();
    return 2.0 * cohesion_pa * std::cos(friction_angle_rad) / (1.0 - s);
}

} // namespace wiredem::engine::analysis
