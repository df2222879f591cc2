#include "analysis/strength.hpp"

#include "analysis/stress.hpp"

#include <algorithm>
#include <cmath>

namespace wiredem::engine::analysis {

const char* to_string(CurveShape shape) noexcept
{
    switch (shape) {
    case CurveShape::peak: return "peak";
    case CurveShape::plateau: return "plateau";
    case CurveShape::rising: return "rising";
    }
    return "rising";
}

namespace {

bool non_decreasing(std::span<const double> strain)
{
    for (std::size_t i = 1; i < strain.size(); ++i)
        if (!(strain[i] >= strain[i - 1])) return false;
    return true;
}

/// First sample at or after the start of the end window.
std::size_t end_window_start(std::span<const double> strain, double window)
{
    const double from = strain.back() - window;
    return static_cast<std::size_t>(std::lower_bound(strain.begin(), strain.end(), from) - strain.begin());
}

} // namespace

std::vector<double> smooth_over_strain(std::span<const double> strain, std::span<const double> value, double width)
{
    const std::size_t n = std::min(strain.size(), value.size());
    std::vector<double> out(n);
    // A sample on the window's edge counts, also where rounding moves it by
    // an ulp: evenly spaced samples then give symmetric windows.
    const double half = (0.5 + 1e-9) * width;
    std::size_t lo = 0, hi = 0; // the window [lo, hi)
    for (std::size_t i = 0; i < n; ++i) {
        while (lo < i && strain[lo] < strain[i] - half) ++lo;
        if (hi < i + 1) hi = i + 1;
        while (hi < n && strain[hi] <= strain[i] + half) ++hi;
        double sum = 0.0;
        std::size_t count = 0;
        for (std::size_t j = lo; j < hi; ++j) // a fresh sum per sample: no drift, same bits on any machine
            if (std::isfinite(value[j])) {
                sum += value[j];
                ++count;
            }
        out[i] = count ? sum / static_cast<double>(count) : std::nan("");
    }
    return out;
}

Result<CurveReading, std::string> read_curve(
    std::span<const double> strain, std::span<const double> smoothed, const CurveTolerances& tol)
{
    if (strain.size() != smoothed.size()) return Err(std::string("strain and curve differ in length"));
    if (strain.empty()) return Err(std::string("no loading sample"));
    if (!non_decreasing(strain)) return Err(std::string("axial strain decreases during loading"));
    CurveReading r;
    bool found = false;
    for (std::size_t i = 0; i < smoothed.size(); ++i)
        if (std::isfinite(smoothed[i]) && (!found || smoothed[i] > r.value)) {
            r.index = i;
            r.value = smoothed[i];
            found = true;
        }
    if (!found) return Err(std::string("no finite sample"));
    if (r.value == 0.0) return Err(std::string("the curve's maximum is 0"));
    // The end: the last finite sample; the window's start: its first finite one.
    std::size_t last = smoothed.size() - 1;
    while (!std::isfinite(smoothed[last])) --last;
    std::size_t first = end_window_start(strain.first(last + 1), tol.end_window_strain);
    while (!std::isfinite(smoothed[first])) ++first;
    const double scale = std::abs(r.value);
    r.end_value = smoothed[last];
    r.drop = (r.value - r.end_value) / scale;
    r.end_rise = (r.end_value - smoothed[first]) / scale;
    if (r.drop > tol.shape_tolerance)
        r.shape = CurveShape::peak;
    else if (r.end_rise > tol.shape_tolerance)
        r.shape = CurveShape::rising;
    else
        r.shape = CurveShape::plateau;
    return r;
}

Result<StrengthReading, std::string> read_strength(std::span<const double> axial_strain,
    std::span<const double> sigma1_pa, std::span<const double> sigma3_pa, const CurveTolerances& tol)
{
    const std::size_t n = axial_strain.size();
    if (sigma1_pa.size() != n || sigma3_pa.size() != n) return Err(std::string("series differ in length"));
    if (n == 0) return Err(std::string("no loading sample"));
    if (!non_decreasing(axial_strain)) return Err(std::string("axial strain decreases during loading"));
    const std::vector<double> s1 = smooth_over_strain(axial_strain, sigma1_pa, tol.smoothing_strain);
    const std::vector<double> s3 = smooth_over_strain(axial_strain, sigma3_pa, tol.smoothing_strain);
    std::vector<double> ratio(n), q(n);
    for (std::size_t i = 0; i < n; ++i) {
        ratio[i] = stress_ratio(s1[i], s3[i]);
        q[i] = deviatoric_stress_pa(s1[i], s3[i]);
    }
    StrengthReading out;
    auto eta = read_curve(axial_strain, ratio, tol);
    if (!eta.ok()) return Err("stress ratio: " + eta.error());
    auto dev = read_curve(axial_strain, q, tol);
    if (!dev.ok()) return Err("deviatoric stress: " + dev.error());
    out.stress_ratio = eta.value();
    out.deviatoric = dev.value();
    out.yield_axial_strain = axial_strain[out.stress_ratio.index];
    out.yield_sigma1_pa = s1[out.stress_ratio.index];
    out.yield_sigma3_pa = s3[out.stress_ratio.index];

    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t i = end_window_start(axial_strain, tol.end_window_strain); i < n; ++i) {
        const double r = stress_ratio(sigma1_pa[i], sigma3_pa[i]);
        if (std::isfinite(r)) {
            sum += r;
            ++count;
        }
    }
    out.residual_stress_ratio = count ? sum / static_cast<double>(count) : std::nan("");
    return out;
}

} // namespace wiredem::engine::analysis
