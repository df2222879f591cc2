// Autocorrelation of the wire's segment strain (the model spec §7).
#include "analysis/autocorrelation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <utility>
#include <vector>

using namespace wiredem::engine::analysis;

namespace {

/// X_t = A sin(2π t / P) + ε_t with ε_t uniform in [−noise, noise] from a fixed LCG.
std::vector<double> noisy_sine(std::size_t n, double period, double amplitude, double noise)
{
    std::vector<double> x(n);
    std::uint64_t state = 12345;
    for (std::size_t t = 0; t < n; ++t) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        const double u = static_cast<double>(state >> 11) / static_cast<double>(1ull << 53); // [0, 1)
        x[t] = amplitude * std::sin(2.0 * std::numbers::pi * static_cast<double>(t) / period) + noise * (2.0 * u - 1.0);
    }
    return x;
}

} // namespace

TEST(Autocorrelation, SineStrainRecoversItsPeriodAtTheFirstMaximum)
{
    const double segment_length_m = 1.25e-3;
    for (std::size_t period : {12u, 40u, 97u}) {
        const std::vector<double> strain = noisy_sine(3000, static_cast<double>(period), 1e-3, 1e-4);
        const auto r = autocorrelation(strain, segment_length_m);
        ASSERT_TRUE(r.ok()) << r.error();
        ASSERT_TRUE(r.value().first_maximum_lag.has_value()) << "period " << period;
        EXPECT_EQ(*r.value().first_maximum_lag, period);
        ASSERT_TRUE(r.value().first_maximum_lag_m.has_value());
        EXPECT_DOUBLE_EQ(*r.value().first_maximum_lag_m, static_cast<double>(period) * segment_length_m);
        EXPECT_EQ(r.value().coefficients.size(), strain.size());
    }
}

TEST(Autocorrelation, MatchesHandComputedCoefficientsOfARamp)
{
    // X = 1,2,3,4: μ = 2.5, σ² = 1.25; deviations −1.5, −0.5, 0.5, 1.5
    const std::vector<double> x = {1.0, 2.0, 3.0, 4.0};
    const auto r = autocorrelation(x, 1.0);
    ASSERT_TRUE(r.ok()) << r.error();
    const std::vector<double>& c = r.value().coefficients;
    ASSERT_EQ(c.size(), 4u);
    EXPECT_DOUBLE_EQ(r.value().mean, 2.5);
    EXPECT_DOUBLE_EQ(r.value().variance, 1.25);
    EXPECT_NEAR(c[0], 1.0, 1e-15);
    EXPECT_NEAR(c[1], (0.75 - 0.25 + 0.75) / (3 * 1.25), 1e-15);
    EXPECT_NEAR(c[2], (-0.75 - 0.75) / (2 * 1.25), 1e-15);
    EXPECT_NEAR(c[3], -2.25 / 1.25, 1e-15);
    EXPECT_FALSE(r.value().first_maximum_lag.has_value()); // monotone decay
    EXPECT_FALSE(r.value().first_maximum_lag_m.has_value());
}

TEST(Autocorrelation, MaxLagLimitsTheCoefficientsAndIsClampedToTheSignal)
{
    const std::vector<double> x = noisy_sine(200, 20.0, 1.0, 0.0);
    const auto short_lags = autocorrelation(x, 1e-3, 10);
    ASSERT_TRUE(short_lags.ok()) << short_lags.error();
    EXPECT_EQ(short_lags.value().coefficients.size(), 11u);
    EXPECT_FALSE(short_lags.value().first_maximum_lag.has_value()); // the maximum at 20 lies beyond
    const auto too_many = autocorrelation(x, 1e-3, 5000);
    ASSERT_TRUE(too_many.ok()) << too_many.error();
    EXPECT_EQ(too_many.value().coefficients.size(), 200u);
    EXPECT_EQ(too_many.value().first_maximum_lag, std::optional<std::size_t>(20));
}

TEST(FirstLocalMaximumLag, SkipsLagZeroAndTheLastLag)
{
    const std::vector<double> interior = {1.0, 0.5, 0.7, 0.2};
    const std::vector<double> at_end = {1.0, 0.5, 0.7};
    const std::vector<double> plateau = {1.0, 0.2, 0.5, 0.5, 0.1};
    EXPECT_EQ(first_local_maximum_lag(interior), std::optional<std::size_t>(2));
    EXPECT_FALSE(first_local_maximum_lag(at_end).has_value());
    EXPECT_EQ(first_local_maximum_lag(plateau), std::optional<std::size_t>(2));
    EXPECT_FALSE(first_local_maximum_lag(std::vector<double>{}).has_value());
}

TEST(PeakProminence, IsTheHeightAboveTheHigherOfTheTwoSidesLowestPoints)
{
    //                              0    1    2    3    4     5    6
    const std::vector<double> r = {1.0, 0.2, 0.6, 0.4, 0.7, -0.5, 0.9};
    // Top at 2: the left side stops at r[0] > 0.6 (low 0.2), the right at r[4] > 0.6 (low 0.4).
    EXPECT_DOUBLE_EQ(peak_prominence(r, 2, 2), 0.6 - 0.4);
    // Top at 4: the left side passes 0.6 and stops at r[0] (low 0.2); the right stops at r[6] (low −0.5).
    EXPECT_DOUBLE_EQ(peak_prominence(r, 4, 4), 0.7 - 0.2);
    // A side that never rises above the top runs to the end of r.
    const std::vector<double> tail = {1.0, 0.1, 0.5, 0.3, 0.4, 0.35};
    EXPECT_DOUBLE_EQ(peak_prominence(tail, 2, 2), 0.5 - 0.3);
    // A top at the end, or one that is not above its neighbour, stands out of nothing.
    EXPECT_EQ(peak_prominence(tail, 5, 5), 0.0);
    EXPECT_EQ(peak_prominence(std::vector<double>{1.0, 0.2, 0.5, 0.5, 0.7}, 2, 2), 0.0);
}

TEST(WhiteNoiseBand, Holds95PercentOfTheCoefficientsOfWhiteNoise)
{
    EXPECT_DOUBLE_EQ(white_noise_band_95(7991, 95), 1.96 / std::sqrt(7896.0));
    // Uniform LCG noise: |R̂(k)| beyond 1.96/√(N − k) at about 5 % of the lags.
    // 400 lags: 20 expected, binomial sd √(400 · 0.05 · 0.95) = 4.4; a band of
    // 1/√(N − k) (one sd) would leave about 128 outside.
    const std::vector<double> noise = noisy_sine(8000, 10.0, 0.0, 1.0);
    const auto r = autocorrelation(noise, 1e-3, 400);
    ASSERT_TRUE(r.ok()) << r.error();
    std::size_t outside = 0;
    for (std::size_t k = 1; k <= 400; ++k) outside += std::abs(r.value().coefficients[k]) > white_noise_band_95(8000, k);
    EXPECT_NEAR(static_cast<double>(outside), 0.05 * 400, 3 * std::sqrt(400 * 0.05 * 0.95));
}

TEST(Autocorrelation, ProminentMaximumOfANoisyWaveIsItsPeriod)
{
    // Uniform noise up to twice the amplitude buries the wave's small lags in
    // bumps that the literal first maximum takes (at k = 3 for P ≥ 37.5 with this
    // LCG; at 48 for P = 97 with a quarter of that noise); the prominent one is
    // the period, within a sample (the maximum of a sampled wave of non-integer
    // period, or one shifted by the noise).
    const double segment_length_m = 1.25e-3;
    for (double period : {12.0, 37.5, 40.0, 97.0})
        for (double noise : {0.5e-3, 2e-3}) {
            const std::vector<double> strain = noisy_sine(3000, period, 1e-3, noise);
            const auto r = autocorrelation(strain, segment_length_m);
            ASSERT_TRUE(r.ok()) << r.error();
            EXPECT_EQ(r.value().samples, strain.size());
            ASSERT_TRUE(r.value().prominent_maximum_lag.has_value()) << "period " << period << ", noise " << noise;
            const std::size_t k = *r.value().prominent_maximum_lag;
            EXPECT_LE(std::abs(static_cast<double>(k) - period), 1.0) << "period " << period << ", noise " << noise;
            EXPECT_DOUBLE_EQ(*r.value().prominent_maximum_lag_m, static_cast<double>(k) * segment_length_m);
            ASSERT_TRUE(r.value().first_maximum_lag.has_value());
            EXPECT_LE(*r.value().first_maximum_lag, k);
        }
    const auto buried = autocorrelation(noisy_sine(3000, 97.0, 1e-3, 2e-3), segment_length_m);
    ASSERT_TRUE(buried.ok());
    ASSERT_TRUE(buried.value().first_maximum_lag.has_value());
    EXPECT_LT(*buried.value().first_maximum_lag, 10u); // what the literal reading reports
}

namespace {

/// R̂ of the study's helix column at 80 kPa in outline (7991 segments): a decay
/// from 1 to a shoulder at 0.135 with a bump of 10⁻⁴ at k = 32, a dip to −0.034
/// at 62 and a real maximum of 0.12 at 95, then 0.05 at 120 and a tail to 0 at
/// 200: piecewise linear through those knots, 251 lags.
std::vector<double> helix_shoulder()
{
    const std::vector<std::pair<std::size_t, double>> knots = {{0, 1.0}, {10, 0.4}, {20, 0.2}, {30, 0.136},
        {31, 0.1352}, {32, 0.1353}, {33, 0.1350}, {62, -0.034}, {95, 0.12}, {120, 0.05}, {200, 0.0}, {250, 0.01}};
    std::vector<double> r;
    for (std::size_t i = 0; i + 1 < knots.size(); ++i) {
        const auto [k0, r0] = knots[i];
        const auto [k1, r1] = knots[i + 1];
        for (std::size_t k = k0; k < k1; ++k)
            r.push_back(r0 + (r1 - r0) * static_cast<double>(k - k0) / static_cast<double>(k1 - k0));
    }
    r.push_back(knots.back().second);
    return r;
}

std::vector<double> band_of(std::size_t samples, std::size_t lags)
{
    std::vector<double> band(lags);
    for (std::size_t k = 0; k < lags; ++k) band[k] = white_noise_band_95(samples, k);
    return band;
}

} // namespace

TEST(FirstProminentMaximumLag, SkipsTheShoulderBumpForTheRealHump)
{
    const std::vector<double> r = helix_shoulder();
    ASSERT_EQ(r.size(), 251u);
    EXPECT_EQ(first_local_maximum_lag(r), std::optional<std::size_t>(32));
    EXPECT_NEAR(peak_prominence(r, 32, 32), 1e-4, 1e-12);
    EXPECT_EQ(first_prominent_maximum_lag(r, band_of(7991, r.size())), std::optional<std::size_t>(95));
    // The hump stands 0.12 above the tail's 0 (the higher of −0.034 and 0).
    EXPECT_NEAR(peak_prominence(r, 95, 95), 0.12, 1e-12);
}

TEST(FirstProminentMaximumLag, NoneOnAPureDecay)
{
    std::vector<double> r(300);
    for (std::size_t k = 0; k < r.size(); ++k) r[k] = std::exp(-static_cast<double>(k) / 20.0);
    EXPECT_FALSE(first_local_maximum_lag(r).has_value());
    EXPECT_FALSE(first_prominent_maximum_lag(r, band_of(5000, r.size())).has_value());
    const std::vector<double> zero_band(r.size(), 0.0);
    EXPECT_FALSE(first_prominent_maximum_lag(r, zero_band).has_value());
}

TEST(FirstProminentMaximumLag, AMaximumCountsOnlyWhenItsProminenceExceedsTheBand)
{
    // Binary fractions: the prominence r[3] − 0.25 is exact. The left low is r[2]
    // = 0.25 (r[0] is above), the right side falls to −0.25, so the col is 0.25.
    const double band_value = 0.0625;
    const std::vector<double> band(7, band_value);
    const auto with_bump = [](double p) { return std::vector<double>{1.0, 0.5, 0.25, 0.25 + p, 0.25, 0.0, -0.25}; };
    const double ulp_step = std::ldexp(1.0, -30);
    EXPECT_FALSE(first_prominent_maximum_lag(with_bump(band_value - ulp_step), band).has_value());
    EXPECT_FALSE(first_prominent_maximum_lag(with_bump(band_value), band).has_value()); // equal does not exceed
    EXPECT_EQ(first_prominent_maximum_lag(with_bump(band_value + ulp_step), band), std::optional<std::size_t>(3));
    // The band is read at the maximum's lag.
    std::vector<double> wider = band;
    wider[3] = 2 * band_value;
    EXPECT_FALSE(first_prominent_maximum_lag(with_bump(band_value + ulp_step), wider).has_value());
    // Lags beyond the band's values never qualify.
    EXPECT_FALSE(first_prominent_maximum_lag(with_bump(band_value + ulp_step), std::span(band).first(3)).has_value());
}

TEST(FirstProminentMaximumLag, APlateauTopIsReportedAtItsFirstIndexAndAStepIsNoMaximum)
{
    const std::vector<double> band(8, 0.1);
    const std::vector<double> plateau = {1.0, 0.2, 0.5, 0.5, 0.5, 0.1, 0.0, -0.1};
    EXPECT_EQ(first_prominent_maximum_lag(plateau, band), std::optional<std::size_t>(2));
    EXPECT_DOUBLE_EQ(peak_prominence(plateau, 2, 4), 0.5 - 0.2);
    // A level run that rises again is a step: the literal reading stops on it, the prominent one goes on.
    const std::vector<double> step = {1.0, 0.2, 0.5, 0.5, 0.7, 0.1, 0.0, -0.1};
    EXPECT_EQ(first_local_maximum_lag(step), std::optional<std::size_t>(2));
    EXPECT_EQ(first_prominent_maximum_lag(step, band), std::optional<std::size_t>(4));
}

TEST(FirstProminentMaximumLag, TheLastLagNeverCounts)
{
    const std::vector<double> band(5, 0.0);
    EXPECT_FALSE(first_prominent_maximum_lag(std::vector<double>{1.0, 0.2, 0.1, 0.0, 0.9}, band).has_value());
    EXPECT_FALSE(first_prominent_maximum_lag(std::vector<double>{1.0, 0.2, 0.1, 0.6, 0.6}, band).has_value());
    EXPECT_EQ(first_prominent_maximum_lag(std::vector<double>{1.0, 0.2, 0.1, 0.6, 0.5}, band), std::optional<std::size_t>(3));
    EXPECT_FALSE(first_prominent_maximum_lag(std::vector<double>{}, band).has_value());
    EXPECT_FALSE(first_prominent_maximum_lag(std::vector<double>{1.0}, band).has_value());
}

TEST(Autocorrelation, RejectsAConstantSignal)
{
    const std::vector<double> zeros(100, 0.0);
    const std::vector<double> tenths(100, 0.1); // rounding leaves a tiny σ² in the mean
    const auto a = autocorrelation(zeros, 1e-3);
    const auto b = autocorrelation(tenths, 1e-3);
    ASSERT_FALSE(a.ok());
    ASSERT_FALSE(b.ok());
    EXPECT_NE(a.error().find("constant"), std::string::npos) << a.error();
    EXPECT_NE(b.error().find("constant"), std::string::npos) << b.error();
}

TEST(Autocorrelation, RejectsTooShortSignals)
{
    EXPECT_FALSE(autocorrelation(std::vector<double>{}, 1e-3).ok());
    EXPECT_FALSE(autocorrelation(std::vector<double>{1.0}, 1e-3).ok());
    EXPECT_TRUE(autocorrelation(std::vector<double>{1.0, 2.0}, 1e-3).ok());
}

TEST(Autocorrelation, RejectsNonFiniteSamplesAndBadSegmentLength)
{
    std::vector<double> x = noisy_sine(50, 10.0, 1.0, 0.0);
    EXPECT_FALSE(autocorrelation(x, 0.0).ok());
    EXPECT_FALSE(autocorrelation(x, -1e-3).ok());
    EXPECT_FALSE(autocorrelation(x, std::numeric_limits<double>::infinity()).ok());
    x[17] = std::numeric_limits<double>::quiet_NaN();
    const auto r = autocorrelation(x, 1e-3);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("sample 17"), std::string::npos) << r.error();
}
