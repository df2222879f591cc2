// Mohr–Coulomb envelope (the model spec §7) against circles built from a known envelope.
#include "analysis/mohr_coulomb.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

using namespace wiredem::engine::analysis;

namespace {

constexpr double deg = std::numbers::pi / 180.0;

/// Peak state whose Mohr circle touches τ = c + σ tan φ at confining pressure σ₃:
/// t = c cos φ + p sin φ with p = σ₃ + t  ⇒  t = (c cos φ + σ₃ sin φ)/(1 − sin φ).
PeakState tangent_peak(double phi_rad, double cohesion_pa, double sigma3_pa)
{
    const double t = (cohesion_pa * std::cos(phi_rad) + sigma3_pa * std::sin(phi_rad)) / (1.0 - std::sin(phi_rad));
    return {sigma3_pa + 2.0 * t, sigma3_pa};
}

std::vector<PeakState> tangent_peaks(double phi_rad, double cohesion_pa)
{
    std::vector<PeakState> peaks;
    for (double s3 : {25e3, 50e3, 100e3, 200e3}) peaks.push_back(tangent_peak(phi_rad, cohesion_pa, s3));
    return peaks;
}

} // namespace

TEST(MohrCoulombFit, RecoversFrictionAngleAndCohesionOfTangentCircles)
{
    const std::vector<PeakState> peaks = tangent_peaks(35.0 * deg, 12e3);
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_TRUE(fit.ok()) << fit.error();
    EXPECT_NEAR(fit.value().friction_angle_rad, 35.0 * deg, 1e-9 * 35.0 * deg);
    EXPECT_NEAR(fit.value().cohesion_pa, 12e3, 1e-9 * 12e3);
    ASSERT_TRUE(fit.value().r_squared.has_value());
    EXPECT_NEAR(*fit.value().r_squared, 1.0, 1e-12);
    EXPECT_FALSE(fit.value().cohesion_fixed_at_zero);
}

TEST(MohrCoulombFit, ReportsOneCirclePerTestInInputOrder)
{
    const std::vector<PeakState> peaks = {{300e3, 100e3}, {500e3, 200e3}, {180e3, 50e3}};
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_TRUE(fit.ok()) << fit.error();
    ASSERT_EQ(fit.value().circles.size(), 3u);
    EXPECT_DOUBLE_EQ(fit.value().circles[0].centre_pa, 200e3);
    EXPECT_DOUBLE_EQ(fit.value().circles[0].radius_pa, 100e3);
    EXPECT_DOUBLE_EQ(fit.value().circles[1].centre_pa, 350e3);
    EXPECT_DOUBLE_EQ(fit.value().circles[1].radius_pa, 150e3);
    EXPECT_DOUBLE_EQ(fit.value().circles[2].centre_pa, 115e3);
    EXPECT_DOUBLE_EQ(fit.value().circles[2].radius_pa, 65e3);
}

TEST(MohrCoulombFit, PaperTopLineAngleIsArctanOfSlopeAndBelowFrictionAngle)
{
    const auto fit = fit_mohr_coulomb(tangent_peaks(35.0 * deg, 12e3));
    ASSERT_TRUE(fit.ok()) << fit.error();
    const double tan_alpha = std::sin(35.0 * deg); // sin φ = tan α on the exact envelope
    EXPECT_NEAR(fit.value().slope, tan_alpha, 1e-12);
    EXPECT_NEAR(fit.value().paper_top_line_angle_rad, std::atan(tan_alpha), 1e-12);
    EXPECT_LT(fit.value().paper_top_line_angle_rad, fit.value().friction_angle_rad);
    EXPECT_NEAR(fit.value().intercept_pa, 12e3 * std::cos(35.0 * deg), 1e-6); // a = c cos φ
}

TEST(MohrCoulombFit, NoisyPeaksGiveRSquaredBelowOneAndANearbyEnvelope)
{
    std::vector<PeakState> peaks = tangent_peaks(35.0 * deg, 12e3);
    const double noise_pa[] = {+3e3, -2e3, +1.5e3, -2.5e3}; // deterministic, a few % of q
    for (std::size_t i = 0; i < peaks.size(); ++i) peaks[i].sigma1_pa += noise_pa[i];
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_TRUE(fit.ok()) << fit.error();
    ASSERT_TRUE(fit.value().r_squared.has_value());
    EXPECT_LT(*fit.value().r_squared, 1.0);
    EXPECT_GT(*fit.value().r_squared, 0.99);
    EXPECT_NEAR(fit.value().friction_angle_rad, 35.0 * deg, 1.0 * deg);
    EXPECT_NEAR(fit.value().cohesion_pa, 12e3, 3e3);
}

TEST(MohrCoulombFit, TwoPressuresFitExactly)
{
    const std::vector<PeakState> all = tangent_peaks(30.0 * deg, 5e3);
    const std::vector<PeakState> peaks = {all[0], all[3]};
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_TRUE(fit.ok()) << fit.error();
    EXPECT_NEAR(fit.value().friction_angle_rad, 30.0 * deg, 1e-9);
    EXPECT_NEAR(fit.value().cohesion_pa, 5e3, 1e-9 * 5e3);
    EXPECT_NEAR(*fit.value().r_squared, 1.0, 1e-12);
}

TEST(MohrCoulombFit, SinglePressureGivesFrictionAngleWithCohesionFixedAtZero)
{
    // c = 0, φ = 30°: σ₁/σ₃ = (1 + sin φ)/(1 − sin φ) = 3
    const std::vector<PeakState> peaks = {{300e3, 100e3}};
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_TRUE(fit.ok()) << fit.error();
    EXPECT_NEAR(fit.value().friction_angle_rad, 30.0 * deg, 1e-12);
    EXPECT_EQ(fit.value().cohesion_pa, 0.0);
    EXPECT_TRUE(fit.value().cohesion_fixed_at_zero);
    EXPECT_FALSE(fit.value().r_squared.has_value());
    EXPECT_NEAR(fit.value().paper_top_line_angle_rad, std::atan(0.5), 1e-12); // t/p = 100/200
}

TEST(MohrCoulombFit, RejectsEmptyInput)
{
    const auto fit = fit_mohr_coulomb({});
    ASSERT_FALSE(fit.ok());
    EXPECT_NE(fit.error().find("no tests"), std::string::npos) << fit.error();
}

TEST(MohrCoulombFit, RejectsNonFiniteStressNamingTheTest)
{
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const std::vector<PeakState> with_nan = {{300e3, 100e3}, {nan, 200e3}};
    const std::vector<PeakState> with_inf = {{300e3, 100e3}, {500e3, 200e3}, {600e3, inf}};
    const auto a = fit_mohr_coulomb(with_nan);
    const auto b = fit_mohr_coulomb(with_inf);
    ASSERT_FALSE(a.ok());
    ASSERT_FALSE(b.ok());
    EXPECT_NE(a.error().find("test 1"), std::string::npos) << a.error();
    EXPECT_NE(b.error().find("test 2"), std::string::npos) << b.error();
}

TEST(MohrCoulombFit, RejectsSlopeOfOneOrMoreWhichHasNoRealFrictionAngle)
{
    // t rises faster than p when σ₃ falls while σ₁ rises: slope 125/75 > 1.
    const std::vector<PeakState> peaks = {{200e3, 100e3}, {400e3, 50e3}};
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_FALSE(fit.ok());
    EXPECT_NE(fit.error().find("no real friction angle"), std::string::npos) << fit.error();
}

TEST(MohrCoulombFit, RejectsTestsThatAllShareOneCircleCentre)
{
    const std::vector<PeakState> peaks = {{300e3, 100e3}, {250e3, 150e3}}; // p = 200 kPa twice
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_FALSE(fit.ok());
    EXPECT_NE(fit.error().find("same circle centre"), std::string::npos) << fit.error();
}

TEST(MohrCoulombFit, RejectsPeakWithSigma1BelowSigma3)
{
    const std::vector<PeakState> peaks = {{300e3, 100e3}, {90e3, 100e3}};
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_FALSE(fit.ok());
    EXPECT_NE(fit.error().find("below sigma3_pa"), std::string::npos) << fit.error();
}

TEST(MohrCoulombFit, RejectsSingleTestWithoutPositiveMeanStress)
{
    const std::vector<PeakState> peaks = {{0.0, 0.0}};
    EXPECT_FALSE(fit_mohr_coulomb(peaks).ok());
}
