// Least-squares Mohr–Coulomb envelope; see mohr_coulomb.hpp.
#include "analysis/mohr_coulomb.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace wiredem::engine::analysis {

namespace {

std::string format_pa(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

std::string test_label(std::size_t i) { return "test " + std::to_string(i); }

} // namespace

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
                + format_pa(s.sigma1_pa) + ", sigma3_pa = " + format_pa(s.sigma3_pa) + ")"};
        if (s.sigma1_pa < s.sigma3_pa)
            return Err{"mohr_coulomb: " + test_label(i) + " has sigma1_pa = " + format_pa(s.sigma1_pa)
                + " below sigma3_pa = " + format_pa(s.sigma3_pa) + " (not a compression peak)"};
        fit.circles.push_back(mohr_circle(s));
    }

    const std::size_t n = fit.circles.size();
    if (n == 1) {
        // One circle: the envelope through the origin tangent to it, sin φ = t/p, c = 0.
        const MohrCircle& m = fit.circles.front();
        if (!(m.centre_pa > 0.0))
            return Err{"mohr_coulomb: single test with circle centre p = " + format_pa(m.centre_pa)
                + " Pa; need p > 0 to fit phi with c = 0"};
        fit.slope = m.radius_pa / m.centre_pa;
        fit.intercept_pa = 0.0;
        fit.cohesion_fixed_at_zero = true;
    } else {
        bool all_same_centre = true;
        for (const MohrCircle& m : fit.circles)
            all_same_centre = all_same_centre && m.centre_pa == fit.circles.front().centre_pa;
        if (all_same_centre)
            return Err{"mohr_coulomb: all " + std::to_string(n) + " tests have the same circle centre p = "
                + format_pa(fit.circles.front().centre_pa) + " Pa; the slope is undefined"};

        // Centred sums (numerically stable): slope = S_pt / S_pp, a = t̄ − slope·p̄.
        double p_mean = 0.0, t_mean = 0.0;
        for (const MohrCircle& m : fit.circles) {
            p_mean += m.centre_pa;
            t_mean += m.radius_pa;
        }
        p_mean /= static_cast<double>(n);
        t_mean /= static_cast<double>(n);
        double s_pp = 0.0, s_pt = 0.0, s_tt = 0.0;
        for (const MohrCircle& m : fit.circles) {
            const double dp = m.centre_pa - p_mean, dt = m.radius_pa - t_mean;
            s_pp += dp * dp;
            s_pt += dp * dt;
            s_tt += dt * dt;
        }
        fit.slope = s_pt / s_pp;
        fit.intercept_pa = t_mean - fit.slope * p_mean;

        double ss_res = 0.0;
        for (const MohrCircle& m : fit.circles) {
            const double r = m.radius_pa - (fit.intercept_pa + fit.slope * m.centre_pa);
            ss_res += r * r;
        }
        // SS_tot = 0 means every t is equal; the horizontal line then fits exactly.
        fit.r_squared = s_tt > 0.0 ? 1.0 - ss_res / s_tt : 1.0;
    }

    if (!(std::abs(fit.slope) < 1.0))
        return Err{"mohr_coulomb: slope of the line through the circle tops tan(alpha) = " + format_pa(fit.slope)
            + " has magnitude >= 1; no real friction angle (sin(phi) = tan(alpha))"};

    fit.friction_angle_rad = std::asin(fit.slope);                         // sin φ = tan α
    fit.cohesion_pa = fit.intercept_pa / std::cos(fit.friction_angle_rad); // c = a / cos φ
    fit.paper_top_line_angle_rad = std::atan(fit.slope);                   // the paper's reading of φ
    return fit;
}

} // namespace wiredem::engine::analysis
