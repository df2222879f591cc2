// Grain size distributions (issue 40, part 1): a sieve curve as a
// geotechnical lab reports it (sizes and the fraction passing, by mass) or a
// number distribution in the same form, the inverse of its number CDF (from
// which the preparation draws one grain per uniform number, so a draw costs
// what the uniform spread's did), and the figures a lab reads off a curve
// (D10, D50, D60, C_u) for what was asked and what was drawn, with the
// Kolmogorov–Smirnov distance between the two.
//
// Between two sizes of the curve the fraction passing is linear in log D,
// the semi-logarithmic interpolation with which grading curves are drawn and
// their D-values read (ASTM D6913). So within an interval [a, b] the density
// of the given basis per unit D is w/D (w = ΔP / ln(b/a)), and the number
// density is w D^p with p = −4 for a mass curve (a grain's mass ∝ D³) and
// p = −1 for a number curve; the mass density is w D^{p+3}. Every CDF and its
// inverse is then in closed form (docs/model.md, "Size distribution").
//
// Sizes are diameters (sieve apertures); the engine's radius is D/2. Pure and
// thread-safe.
#pragma once

#include "specimen/sieve_basis.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace wiredem::engine {

/// A size distribution as a lab reports it.
struct SieveCurve {
    /// What the fractions count: mass (a sieve analysis) or number (a count).
    using Basis = SieveBasis;
    Basis basis = Basis::mass;
    /// D_k, grain diameters (sieve apertures) [m]: at least 2, strictly
    /// increasing, positive.
    std::vector<double> diameters_m;
    /// P_k, the fraction passing D_k (smaller than D_k): nondecreasing in
    /// [0, 1], starting at 0 and ending at 1.
    std::vector<double> fraction_passing;
    friend bool operator==(const SieveCurve&, const SieveCurve&) = default;
};

/// A sieve curve made ready to draw from and to read: the number and mass
/// weights of each interval. Construct only from a valid curve (api/
/// validates it; a curve whose fractions never rise has no grains).
class GrainSizeDistribution {
public:
    explicit GrainSizeDistribution(const SieveCurve& curve);

    [[nodiscard]] double smallest_diameter_m() const { return d_.front(); }
    [[nodiscard]] double largest_diameter_m() const { return d_.back(); }
    /// E[D³] over grains (by number) [m³]: the mean grain volume is (π/6) this.
    [[nodiscard]] double mean_cubed_diameter_m3() const { return mean_cubed_m3_; }

    /// Fraction of the grains by number with a diameter ≤ d.
    [[nodiscard]] double number_fraction_below(double d_m) const { return fraction_below(d_m, number_cum_, p_); }
    /// Fraction of the grains' mass in grains with a diameter ≤ d.
    [[nodiscard]] double mass_fraction_below(double d_m) const { return fraction_below(d_m, mass_cum_, p_ + 3); }
    /// The diameter below which a fraction u ∈ [0, 1] of the grains lie, by
    /// number: drawing u uniformly draws a grain of the distribution [m].
    [[nodiscard]] double diameter_at_number_fraction(double u) const { return diameter_at(u, number_cum_, p_); }
    /// D_x: the diameter below which a fraction x ∈ [0, 1] of the mass lies
    /// (D10 = diameter_at_mass_fraction(0.1)) [m].
    [[nodiscard]] double diameter_at_mass_fraction(double x) const { return diameter_at(x, mass_cum_, p_ + 3); }

private:
    [[nodiscard]] double fraction_below(double d_m, const std::vector<double>& cum, int q) const;
    [[nodiscard]] double diameter_at(double u, const std::vector<double>& cum, int q) const;

    std::vector<double> d_;          ///< the curve's diameters [m]
    std::vector<double> number_cum_; ///< number fraction below each diameter
    std::vector<double> mass_cum_;   ///< mass fraction below each diameter
    int p_ = -4;                     ///< number density ∝ D^p within an interval
    double mean_cubed_m3_ = 0.0;
};

/// What a lab reads off a grading curve: the diameters below which 10, 50
/// and 60 % of the mass lie and the uniformity coefficient C_u = D60/D10.
struct GradingFigures {
    double d10_m = 0.0, d50_m = 0.0, d60_m = 0.0;
    double uniformity_coefficient = 0.0;
};

/// The requested distribution's figures.
[[nodiscard]] GradingFigures grading_figures(const GrainSizeDistribution& requested);

/// The drawn grains' figures: D_x is the smallest drawn diameter at which
/// the cumulative mass of the grains sorted by size reaches x.
/// @param diameters_m  the drawn grains' diameters, any order, at least one
[[nodiscard]] GradingFigures grading_figures(std::span<const double> diameters_m);

/// The Kolmogorov–Smirnov distance sup |F_n − F| between the drawn grains'
/// empirical CDF by number and the requested one (by number: the grains are
/// drawn independently by number, so the statistic's distribution is the
/// classical one). At least one diameter.
[[nodiscard]] double kolmogorov_smirnov_distance(std::span<const double> diameters_m,
    const GrainSizeDistribution& requested);

/// The Kolmogorov–Smirnov critical distance at significance 1 % for n
/// independent draws, from the asymptotic distribution: 1.628/√n (within
/// 1 % of the exact one from n = 35; conservative below about that).
[[nodiscard]] double kolmogorov_smirnov_critical_1pct(std::size_t n);

/// The distribution of the drawn grains against the requested one, as a
/// preparation reports it.
struct GrainSizeReport {
    GradingFigures requested, drawn;
    double ks_distance = 0.0;       ///< kolmogorov_smirnov_distance of the grains poured
    double ks_critical_1pct = 0.0;  ///< the distance that a true draw exceeds with probability 1 %
    std::size_t grains = 0;         ///< grains drawn
};

/// The report for the drawn grains' radii [m] (at least one).
[[nodiscard]] GrainSizeReport grain_size_report(std::span<const double> radii_m, const SieveCurve& requested);

} // namespace wiredem::engine
