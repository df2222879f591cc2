// Autocorrelation of the wire's segment strain (the model spec §7).
#include "analysis/autocorrelation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
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
