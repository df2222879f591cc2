#include "specimen/grain_sizes.hpp"

#include "core/assert.hpp"

#include <algorithm>
#include <cmath>

namespace wiredem::engine {
namespace {

/// ∫_a^x D^q dD.
double power_integral(int q, double a, double x)
{
    if (q == -1) return std::log(x / a);
    return (std::pow(x, q + 1) - std::pow(a, q + 1)) / (q + 1);
}

/// The x in [a, b] at which ∫_a^x D^q dD is a fraction g of ∫_a^b D^q dD.
double power_inverse(int q, double a, double b, double g)
{
    if (q == -1) return a * std::exp(g * std::log(b / a));
    const double lo = std::pow(a, q + 1), hi = std::pow(b, q + 1);
    return std::clamp(std::pow(lo + g * (hi - lo), 1.0 / (q + 1)), a, b);
}

} // namespace

GrainSizeDistribution::GrainSizeDistribution(const SieveCurve& curve)
    : d_(curve.diameters_m), p_(curve.basis == SieveCurve::Basis::mass ? -4 : -1)
{
    const std::size_t n = d_.size();
    WIREDEM_ASSERT(n >= 2 && curve.fraction_passing.size() == n, "a curve has two sizes or more, a fraction for each");
    number_cum_.assign(n, 0.0);
    mass_cum_.assign(n, 0.0);
    // Interval k: the given basis has density w/D, w = ΔP / ln(b/a); by
    // number w D^p, by mass w D^{p+3} (up to the constant πρ/6).
    for (std::size_t k = 0; k + 1 < n; ++k) {
        const double a = d_[k], b = d_[k + 1];
        const double w = (curve.fraction_passing[k + 1] - curve.fraction_passing[k]) / std::log(b / a);
        number_cum_[k + 1] = number_cum_[k] + w * power_integral(p_, a, b);
        mass_cum_[k + 1] = mass_cum_[k] + w * power_integral(p_ + 3, a, b);
    }
    const double number = number_cum_.back(), mass = mass_cum_.back();
    WIREDEM_ASSERT(number > 0.0 && mass > 0.0, "the curve's fractions rise somewhere");
    mean_cubed_m3_ = mass / number;
    for (std::size_t k = 0; k < n; ++k) {
        number_cum_[k] /= number;
        mass_cum_[k] /= mass;
    }
    number_cum_.back() = mass_cum_.back() = 1.0;
}

double GrainSizeDistribution::fraction_below(double d_m, const std::vector<double>& cum, int q) const
{
    if (!(d_m > d_.front())) return 0.0;
    if (!(d_m < d_.back())) return 1.0;
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(d_.begin(), d_.end(), d_m) - d_.begin()) - 1;
    const double a = d_[k], b = d_[k + 1];
    return cum[k] + (cum[k + 1] - cum[k]) * power_integral(q, a, d_m) / power_integral(q, a, b);
}

double GrainSizeDistribution::diameter_at(double u, const std::vector<double>& cum, int q) const
{
    if (!(u > 0.0)) return d_.front();
    if (!(u < 1.0)) return d_.back();
    // cum[k] ≤ u < cum[k + 1]: an interval of positive weight.
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(cum.begin(), cum.end(), u) - cum.begin()) - 1;
    return power_inverse(q, d_[k], d_[k + 1], (u - cum[k]) / (cum[k + 1] - cum[k]));
}

GradingFigures grading_figures(const GrainSizeDistribution& requested)
{
    GradingFigures f;
    f.d10_m = requested.diameter_at_mass_fraction(0.1);
    f.d50_m = requested.diameter_at_mass_fraction(0.5);
    f.d60_m = requested.diameter_at_mass_fraction(0.6);
    f.uniformity_coefficient = f.d60_m / f.d10_m;
    return f;
}

GradingFigures grading_figures(std::span<const double> diameters_m)
{
    WIREDEM_ASSERT(!diameters_m.empty(), "grading figures of no grains");
    std::vector<double> d(diameters_m.begin(), diameters_m.end());
    std::sort(d.begin(), d.end());
    std::vector<double> cum(d.size());
    double mass = 0.0;
    for (std::size_t i = 0; i < d.size(); ++i) cum[i] = mass += d[i] * d[i] * d[i];
    auto at = [&](double x) {
        const auto it = std::lower_bound(cum.begin(), cum.end(), x * mass);
        return d[std::min(static_cast<std::size_t>(it - cum.begin()), d.size() - 1)];
    };
    GradingFigures f;
    f.d10_m = at(0.1);
    f.d50_m = at(0.5);
    f.d60_m = at(0.6);
    f.uniformity_coefficient = f.d60_m / f.d10_m;
    return f;
}

double kolmogorov_smirnov_distance(std::span<const double> diameters_m, const GrainSizeDistribution& requested)
{
    WIREDEM_ASSERT(!diameters_m.empty(), "a distance of no grains");
    std::vector<double> d(diameters_m.begin(), diameters_m.end());
    std::sort(d.begin(), d.end());
    const double n = static_cast<double>(d.size());
    double distance = 0.0;
    for (std::size_t i = 0; i < d.size(); ++i) {
        const double f = requested.number_fraction_below(d[i]);
        distance = std::max({distance, static_cast<double>(i + 1) / n - f, f - static_cast<double>(i) / n});
    }
    return distance;
}

double kolmogorov_smirnov_critical_1pct(std::size_t n)
{
    // c(α) = √(−ln(α/2)/2) = 1.6276 at α = 0.01.
    return std::sqrt(-0.5 * std::log(0.005)) / std::sqrt(static_cast<double>(n));
}

GrainSizeReport grain_size_report(std::span<const double> radii_m, const SieveCurve& requested)
{
    std::vector<double> d(radii_m.size());
    std::transform(radii_m.begin(), radii_m.end(), d.begin(), [](double r) { return 2.0 * r; });
    const GrainSizeDistribution dist(requested);
    GrainSizeReport r;
    r.requested = grading_figures(dist);
    r.drawn = grading_figures(d);
    r.ks_distance = kolmogorov_smirnov_distance(d, dist);
    r.ks_critical_1pct = kolmogorov_smirnov_critical_1pct(d.size());
    r.grains = d.size();
    return r;
}

} // namespace wiredem::engine
