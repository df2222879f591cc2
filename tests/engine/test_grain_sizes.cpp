// Grain size distributions (engine/specimen/grain_sizes.hpp): grains drawn
// from a curve reproduce it within the statistics of the sample, judged
// against the curve as given (the fraction passing each sieve) and by the
// Kolmogorov–Smirnov test; a mass curve and a number curve of one interval
// give the medians their closed forms say.
#include "scene.hpp"
#include "specimen/grain_sizes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <tuple>
#include <vector>

using namespace wiredem::engine;

namespace {

/// n diameters drawn from the curve as the preparation draws them: one
/// uniform number each, through the inverse number CDF.
std::vector<double> draw(const SieveCurve& curve, std::size_t n, std::uint64_t seed)
{
    const GrainSizeDistribution dist(curve);
    SplitMix64 rng(seed);
    std::vector<double> d(n);
    for (double& x : d) x = dist.diameter_at_number_fraction(rng.uniform());
    return d;
}

/// A gravel's sieve analysis: 2–16 mm, by mass.
SieveCurve gravel_curve()
{
    SieveCurve c;
    c.basis = SieveCurve::Basis::mass;
    c.diameters_m = {2e-3, 4e-3, 8e-3, 11.2e-3, 16e-3};
    c.fraction_passing = {0.0, 0.1, 0.45, 0.8, 1.0};
    return c;
}

/// The fraction of the sample's mass (∝ D³) in grains below `size`, and its
/// standard error as a ratio estimator: Var ≈ Σ (D³ (1{D<size} − f))² / (Σ D³)².
struct MassFraction {
    double fraction, sigma;
};
MassFraction mass_fraction_below(const std::vector<double>& d, double size)
{
    double below = 0.0, total = 0.0;
    for (double x : d) {
        total += x * x * x;
        if (x < size) below += x * x * x;
    }
    const double f = below / total;
    double var = 0.0;
    for (double x : d) {
        const double e = x * x * x * ((x < size ? 1.0 : 0.0) - f);
        var += e * e;
    }
    return {f, std::sqrt(var) / total};
}

} // namespace

TEST(GrainSizes, DrawnGravelPassesEachSieveWithTheMassTheCurveGives)
{
    // The fraction passing each sieve, by mass, in 20 000 drawn grains,
    // against the curve's own P_k: within 4 standard errors of the sample
    // (a false alarm has probability 6e-5 per sieve).
    const SieveCurve curve = gravel_curve();
    const std::vector<double> d = draw(curve, 20000, 7);
    for (std::size_t k = 1; k + 1 < curve.diameters_m.size(); ++k) {
        const MassFraction m = mass_fraction_below(d, curve.diameters_m[k]);
        EXPECT_NEAR(m.fraction, curve.fraction_passing[k], 4.0 * m.sigma) << "sieve " << curve.diameters_m[k];
    }
    const GrainSizeDistribution dist(curve);
    for (double x : d) {
        ASSERT_GE(x, dist.smallest_diameter_m());
        ASSERT_LE(x, dist.largest_diameter_m());
    }
}

TEST(GrainSizes, DrawnGrainsPassTheKolmogorovSmirnovTestAtOnePercent)
{
    for (const SieveCurve::Basis basis : {SieveCurve::Basis::mass, SieveCurve::Basis::number}) {
        SieveCurve curve = gravel_curve();
        curve.basis = basis;
        const GrainSizeDistribution dist(curve);
        for (std::size_t n : {200u, 5000u}) {
            const std::vector<double> d = draw(curve, n, 11);
            EXPECT_LT(kolmogorov_smirnov_distance(d, dist), kolmogorov_smirnov_critical_1pct(n))
                << "n = " << n << (basis == SieveCurve::Basis::mass ? " by mass" : " by number");
        }
    }
    // And the test has teeth: grains drawn from the number curve fail
    // against the mass curve of the same figures (the mass curve's grains
    // are far smaller by number).
    SieveCurve by_number = gravel_curve();
    by_number.basis = SieveCurve::Basis::number;
    const std::vector<double> d = draw(by_number, 5000, 11);
    EXPECT_GT(kolmogorov_smirnov_distance(d, GrainSizeDistribution(gravel_curve())), kolmogorov_smirnov_critical_1pct(5000));
}

TEST(GrainSizes, MassAndNumberCurvesOfOneIntervalGiveTheirClosedFormMedians)
{
    // One interval [a, b], the fraction linear in log D. By mass: the mass
    // density ∝ 1/D, so D50 = √(ab); the number density ∝ D⁻⁴, so half the
    // grains lie below ((a⁻³ + b⁻³)/2)^{−1/3}. By number: the number
    // density ∝ 1/D, so the number median is √(ab); the mass density ∝ D²,
    // so D50 = ((a³ + b³)/2)^{1/3}.
    const double a = 1e-3, b = 8e-3;
    const double log_mid = std::sqrt(a * b);
    const double mass_curve_number_median = std::pow(0.5 * (std::pow(a, -3) + std::pow(b, -3)), -1.0 / 3.0);
    const double number_curve_mass_median = std::cbrt(0.5 * (a * a * a + b * b * b));
    SieveCurve mass{SieveCurve::Basis::mass, {a, b}, {0.0, 1.0}};
    SieveCurve number{SieveCurve::Basis::number, {a, b}, {0.0, 1.0}};
    const GrainSizeDistribution by_mass(mass), by_number(number);
    EXPECT_NEAR(by_mass.diameter_at_mass_fraction(0.5), log_mid, 1e-12 * b);
    EXPECT_NEAR(by_mass.diameter_at_number_fraction(0.5), mass_curve_number_median, 1e-12 * b);
    EXPECT_NEAR(by_number.diameter_at_number_fraction(0.5), log_mid, 1e-12 * b);
    EXPECT_NEAR(by_number.diameter_at_mass_fraction(0.5), number_curve_mass_median, 1e-12 * b);
    // E[D³] by number: mass curve (ln(b/a)) / ((a⁻³ − b⁻³)/3); number curve
    // ((b³ − a³)/3) / ln(b/a).
    EXPECT_NEAR(by_mass.mean_cubed_diameter_m3(), std::log(b / a) / ((std::pow(a, -3) - std::pow(b, -3)) / 3.0),
        1e-12 * a * a * a);
    EXPECT_NEAR(by_number.mean_cubed_diameter_m3(), (b * b * b - a * a * a) / 3.0 / std::log(b / a), 1e-12 * b * b * b);

    // The drawn grains: half of them by number below the number median and
    // half the mass below D50, within 4 standard errors (binomial for the
    // count, the ratio estimator for the mass).
    const std::size_t n = 20000;
    for (const auto& [curve, number_median, mass_median] :
        {std::tuple{mass, mass_curve_number_median, log_mid}, std::tuple{number, log_mid, number_curve_mass_median}}) {
        const std::vector<double> d = draw(curve, n, 3);
        const double median = number_median; // (clang 14 does not capture a structured binding)
        const double below = static_cast<double>(std::count_if(d.begin(), d.end(), [median](double x) { return x < median; }));
        EXPECT_NEAR(below / static_cast<double>(n), 0.5, 4.0 * std::sqrt(0.25 / static_cast<double>(n)));
        const MassFraction m = mass_fraction_below(d, mass_median);
        EXPECT_NEAR(m.fraction, 0.5, 4.0 * m.sigma);
    }
}

TEST(GrainSizes, GradingFiguresReadTheCurveAndTheSample)
{
    // The curve's D-values, log-linear between the sieves: D10 at the
    // second sieve (P = 0.1) exactly; D60 between 8 and 11.2 mm at
    // (0.6 − 0.45)/(0.8 − 0.45) of the log step.
    const GradingFigures f = grading_figures(GrainSizeDistribution(gravel_curve()));
    EXPECT_NEAR(f.d10_m, 4e-3, 1e-15);
    EXPECT_NEAR(f.d60_m, 8e-3 * std::pow(11.2 / 8.0, 0.15 / 0.35), 1e-15);
    EXPECT_NEAR(f.uniformity_coefficient, f.d60_m / f.d10_m, 1e-15);
    // Equal grains: every D-value is their diameter, C_u = 1.
    const std::vector<double> same(10, 3e-3);
    const GradingFigures s = grading_figures(same);
    EXPECT_EQ(s.d10_m, 3e-3);
    EXPECT_EQ(s.d60_m, 3e-3);
    EXPECT_EQ(s.uniformity_coefficient, 1.0);
    // A sample's D_x is where its cumulative mass reaches x: four grains of
    // 1, 1, 1 and 2 mm hold 1/11 of the mass each in the small ones.
    const std::vector<double> four{2e-3, 1e-3, 1e-3, 1e-3};
    const GradingFigures g = grading_figures(four);
    EXPECT_EQ(g.d10_m, 1e-3);  // 2/11 ≥ 0.1
    EXPECT_EQ(g.d50_m, 2e-3);  // 3/11 < 0.5
}

TEST(GrainSizes, AFlatStepOfTheCurveHoldsNoGrains)
{
    // Nothing between 4 and 8 mm: no grain is drawn there.
    SieveCurve c{SieveCurve::Basis::mass, {2e-3, 4e-3, 8e-3, 16e-3}, {0.0, 0.3, 0.3, 1.0}};
    for (double x : draw(c, 5000, 9)) EXPECT_TRUE(x <= 4e-3 || x >= 8e-3) << x;
    EXPECT_EQ(GrainSizeDistribution(c).mass_fraction_below(6e-3), 0.3);
}

// WIREDEM_ASSERT is on in the sanitizer builds (scripts/build.sh defines
// WIREDEM_ASSERTIONS beside -DNDEBUG): a broken contract aborts there with
// its message, here grading figures asked of no grains.
TEST(GrainSizesDeathTest, FiguresOfNoGrainsAreAProgrammingErrorTheCheckedBuildsStop)
{
#if !defined(NDEBUG) || defined(WIREDEM_ASSERTIONS)
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_DEATH((void)grading_figures(std::span<const double>()), "assertion failed.*grading figures of no grains");
#else
    GTEST_SKIP() << "WIREDEM_ASSERT is compiled out in this build (NDEBUG without WIREDEM_ASSERTIONS)";
#endif
}
