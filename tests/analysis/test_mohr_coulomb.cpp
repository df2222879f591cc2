// Mohr–Coulomb envelope (the model spec §7) against circles built from a known envelope.
#include "analysis/mohr_coulomb.hpp"

#include <gtest/gtest.h>

#include <algorithm>
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

TEST(MohrCoulombFit, TwoPressuresFitExactlyAndSaySoInsteadOfAnRSquared)
{
    const std::vector<PeakState> all = tangent_peaks(30.0 * deg, 5e3);
    const std::vector<PeakState> peaks = {all[0], all[3]};
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_TRUE(fit.ok()) << fit.error();
    EXPECT_NEAR(fit.value().friction_angle_rad, 30.0 * deg, 1e-9);
    EXPECT_NEAR(fit.value().cohesion_pa, 5e3, 1e-9 * 5e3);
    // Two points, two parameters: any line is exact, so R² = 1 would mean nothing.
    EXPECT_FALSE(fit.value().r_squared.has_value());
    EXPECT_EQ(fit.value().caveats, std::vector<FitCaveat>{FitCaveat::two_pressures});
    // The one-parameter c = 0 fit has a degree of freedom left, and c = 5 kPa
    // is not zero: its R² is below 1.
    ASSERT_TRUE(fit.value().cohesionless.r_squared.has_value());
    EXPECT_LT(*fit.value().cohesionless.r_squared, 1.0);
    EXPECT_NE(describe(FitCaveat::two_pressures, fit.value()).find("exact by construction"), std::string::npos);
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

// The constrained fits: least squares of the same tangency condition
// t = a + p tan α (a = c cos φ, tan α = sin φ) with a ≥ 0, tan α ≥ 0, or a = 0.

namespace {

double sum_of_squares(const MohrCoulombFit& fit, double a_pa, double b)
{
    double ss = 0.0;
    for (const MohrCircle& m : fit.circles) ss += (m.radius_pa - a_pa - b * m.centre_pa) * (m.radius_pa - a_pa - b * m.centre_pa);
    return ss;
}

/// No point of a fine grid over the quadrant a ≥ 0, 0 ≤ b < 1 (edges
/// included) has a smaller sum of squares than the envelope `e`: a check of
/// the constrained minimum that does not use the closed forms.
void expect_minimal_over_the_quadrant(const MohrCoulombFit& fit, const MohrEnvelope& e, double a_max_pa)
{
    const double best = sum_of_squares(fit, e.intercept_pa, e.slope);
    for (int i = 0; i <= 400; ++i)
        for (int j = 0; j <= 400; ++j) {
            const double a = a_max_pa * i / 400.0, b = 0.99 * j / 400.0;
            ASSERT_GE(sum_of_squares(fit, a, b), best * (1.0 - 1e-12)) << "a = " << a << " Pa, tan(alpha) = " << b;
        }
}

} // namespace

TEST(MohrCoulombFit, CirclesOfACohesionlessEnvelopeGiveTheCEqualsZeroFitExactly)
{
    const auto fit = fit_mohr_coulomb(tangent_peaks(32.0 * deg, 0.0));
    ASSERT_TRUE(fit.ok()) << fit.error();
    const MohrEnvelope& c0 = fit.value().cohesionless;
    EXPECT_NEAR(c0.friction_angle_rad, 32.0 * deg, 1e-12);
    EXPECT_EQ(c0.cohesion_pa, 0.0);
    EXPECT_EQ(c0.intercept_pa, 0.0);
    ASSERT_TRUE(c0.r_squared.has_value());
    EXPECT_NEAR(*c0.r_squared, 1.0, 1e-12);
    // The free fit finds the same line (c within rounding of 0, which may be
    // either side of it), and so does the fit with c ≥ 0.
    EXPECT_NEAR(fit.value().cohesion_pa, 0.0, 1e-9 * 200e3);
    EXPECT_NEAR(fit.value().nonnegative.friction_angle_rad, 32.0 * deg, 1e-12);
    EXPECT_NEAR(fit.value().nonnegative.cohesion_pa, 0.0, 1e-9 * 200e3);
}

TEST(MohrCoulombFit, CEqualsZeroFitIsTheOneParameterLeastSquaresThroughTheOrigin)
{
    std::vector<PeakState> peaks = tangent_peaks(30.0 * deg, 8e3);
    peaks[1].sigma1_pa -= 4e3;
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_TRUE(fit.ok()) << fit.error();
    const MohrEnvelope& c0 = fit.value().cohesionless;
    // d/db Σ (t − b p)² = 0 at the fitted slope, and no other slope does better.
    double gradient = 0.0, scale = 0.0;
    for (const MohrCircle& m : fit.value().circles) {
        gradient += m.centre_pa * (m.radius_pa - c0.slope * m.centre_pa);
        scale += m.centre_pa * m.radius_pa;
    }
    EXPECT_NEAR(gradient, 0.0, 1e-12 * scale);
    for (double db : {-1e-3, 1e-3}) EXPECT_GT(sum_of_squares(fit.value(), 0.0, c0.slope + db), sum_of_squares(fit.value(), 0.0, c0.slope));
    EXPECT_NEAR(std::sin(c0.friction_angle_rad), c0.slope, 1e-15);
    // c = 8 kPa ignored: a steeper line through the origin, and a worse R².
    EXPECT_GT(c0.friction_angle_rad, fit.value().friction_angle_rad);
    EXPECT_LT(*c0.r_squared, *fit.value().r_squared);
}

TEST(MohrCoulombFit, NegativeFreeCohesionPutsTheNonnegativeFitOnTheBoundCEqualsZero)
{
    // Circles tangent to τ = −5 kPa + σ tan 30°: the free fit finds c < 0 exactly.
    const auto fit = fit_mohr_coulomb(tangent_peaks(30.0 * deg, -5e3));
    ASSERT_TRUE(fit.ok()) << fit.error();
    EXPECT_NEAR(fit.value().cohesion_pa, -5e3, 1e-9 * 5e3);
    EXPECT_EQ(fit.value().caveats, std::vector<FitCaveat>{FitCaveat::negative_cohesion});
    const MohrEnvelope& nn = fit.value().nonnegative;
    EXPECT_EQ(nn.cohesion_pa, 0.0); // on the bound, exactly
    EXPECT_GT(nn.friction_angle_rad, 0.0);
    // On the bound a = 0 the best slope is the c = 0 fit's, and moving off
    // the bound (a > 0) makes it worse: Σ residuals ≤ 0 there (KKT).
    EXPECT_EQ(nn.slope, fit.value().cohesionless.slope);
    double residuals = 0.0;
    for (const MohrCircle& m : fit.value().circles) residuals += m.radius_pa - nn.slope * m.centre_pa;
    EXPECT_LT(residuals, 0.0);
    expect_minimal_over_the_quadrant(fit.value(), nn, 20e3);
    const std::string text = describe(FitCaveat::negative_cohesion, fit.value());
    EXPECT_NE(text.find("c = -5.0 kPa"), std::string::npos) << text;
    EXPECT_NE(text.find("the best fit with c >= 0 and phi >= 0 is the one with c = 0: phi = "), std::string::npos) << text;
}

TEST(MohrCoulombFit, FallingCircleTopsPutTheNonnegativeFitOnTheBoundPhiEqualsZero)
{
    // t falls as p rises (30, 25, 20 kPa at p = 50, 65, 80 kPa): φ < 0 free.
    const std::vector<PeakState> peaks = {{80e3, 20e3}, {90e3, 40e3}, {100e3, 60e3}};
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_TRUE(fit.ok()) << fit.error();
    EXPECT_LT(fit.value().friction_angle_rad, 0.0);
    EXPECT_NE(std::find(fit.value().caveats.begin(), fit.value().caveats.end(), FitCaveat::negative_friction_angle),
        fit.value().caveats.end());
    const MohrEnvelope& nn = fit.value().nonnegative;
    // On the bound φ = 0: τ = c, the mean of the tops (Σ (t − a)² is least at t̄).
    EXPECT_EQ(nn.slope, 0.0);
    EXPECT_NEAR(nn.cohesion_pa, 25e3, 1e-9 * 25e3);
    EXPECT_NEAR(*nn.r_squared, 0.0, 1e-12); // the mean explains nothing of the spread
    expect_minimal_over_the_quadrant(fit.value(), nn, 60e3);
    const std::string text = describe(FitCaveat::negative_friction_angle, fit.value());
    EXPECT_NE(text.find("the best fit with c >= 0 and phi >= 0: phi = 0.0 deg, c = 25.0 kPa, the one with c = 0: phi = "),
        std::string::npos) << text;
}

TEST(MohrCoulombFit, NonnegativeFitIsTheFreeFitWhenThatSatisfiesTheBounds)
{
    std::vector<PeakState> peaks = tangent_peaks(35.0 * deg, 12e3);
    peaks[2].sigma1_pa += 3e3;
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_TRUE(fit.ok()) << fit.error();
    EXPECT_TRUE(fit.value().caveats.empty());
    EXPECT_EQ(fit.value().nonnegative.cohesion_pa, fit.value().cohesion_pa);
    EXPECT_EQ(fit.value().nonnegative.friction_angle_rad, fit.value().friction_angle_rad);
    EXPECT_EQ(fit.value().nonnegative.r_squared, fit.value().r_squared);
    expect_minimal_over_the_quadrant(fit.value(), fit.value().nonnegative, 30e3);
}

TEST(MohrCoulombFit, ANarrowBandOfCirclesIsFlaggedAndAWideOneIsNot)
{
    // σ₃ = 100, 110, 120 kPa: centres ~ 160-190 kPa, a band of ~30 kPa
    // extrapolated over ~160 kPa to σ = 0.
    std::vector<PeakState> narrow;
    for (double s3 : {100e3, 110e3, 120e3}) narrow.push_back(tangent_peak(30.0 * deg, 2e3, s3));
    const auto a = fit_mohr_coulomb(narrow);
    ASSERT_TRUE(a.ok()) << a.error();
    EXPECT_EQ(a.value().caveats, std::vector<FitCaveat>{FitCaveat::narrow_band});
    EXPECT_NE(describe(FitCaveat::narrow_band, a.value()).find("narrow band"), std::string::npos);
    // The edge: centres p and 2p span exactly their distance from 0 (not narrow);
    // a little less is narrow.
    // t = 10 kPa + 0.4 p at p = 100, 200, 160 kPa (σ₁ = p + t, σ₃ = p − t):
    const std::vector<PeakState> edge = {{150e3, 50e3}, {290e3, 110e3}, {234e3, 86e3}};
    const auto b = fit_mohr_coulomb(edge);
    ASSERT_TRUE(b.ok()) << b.error();
    EXPECT_TRUE(b.value().caveats.empty());
    const std::vector<PeakState> inside = {{150e3, 50e3}, {288.6e3, 109.4e3}, {234e3, 86e3}}; // p = 199 kPa
    const auto c = fit_mohr_coulomb(inside);
    ASSERT_TRUE(c.ok()) << c.error();
    EXPECT_EQ(c.value().caveats, std::vector<FitCaveat>{FitCaveat::narrow_band});
    EXPECT_TRUE(fit_mohr_coulomb(tangent_peaks(30.0 * deg, 2e3)).value().caveats.empty());
}

TEST(MohrCoulombFit, OnePressureSaysThatCWasImposed)
{
    const std::vector<PeakState> peaks = {{300e3, 100e3}};
    const auto fit = fit_mohr_coulomb(peaks);
    ASSERT_TRUE(fit.ok()) << fit.error();
    EXPECT_EQ(fit.value().caveats, std::vector<FitCaveat>{FitCaveat::single_pressure});
    EXPECT_EQ(fit.value().cohesionless.slope, fit.value().slope);
    EXPECT_EQ(fit.value().nonnegative.slope, fit.value().slope);
    EXPECT_FALSE(fit.value().cohesionless.r_squared.has_value());
    EXPECT_STREQ(to_string(FitCaveat::single_pressure), "single_pressure");
}

// The unconfined strength is the circle through σ₃ = 0 that touches the
// envelope: its centre q/2 lies q/2 from the line τ = c + σ tan φ, whose
// distance from (σ, 0) is (c + σ tan φ) cos φ. And the envelope fitted to
// circles touching one line predicts that line's unconfined strength.
TEST(UnconfinedStrength, IsTheCircleThroughZeroTouchingTheEnvelope)
{
    for (const double phi : {10.0 * deg, 30.0 * deg, 45.0 * deg})
        for (const double c : {1e3, 20e3}) {
            const double q = unconfined_strength_pa(phi, c);
            EXPECT_NEAR((c + 0.5 * q * std::tan(phi)) * std::cos(phi), 0.5 * q, 1e-9 * q) << phi / deg << "° " << c;
            const auto fit = fit_mohr_coulomb(tangent_peaks(phi, c));
            ASSERT_TRUE(fit.ok()) << fit.error();
            EXPECT_NEAR(unconfined_strength_pa(fit.value().friction_angle_rad, fit.value().cohesion_pa), q, 1e-6 * q);
        }
    EXPECT_EQ(unconfined_strength_pa(30.0 * deg, 0.0), 0.0); // a cohesionless envelope: no unconfined strength
    EXPECT_TRUE(std::isnan(unconfined_strength_pa(90.0 * deg, 1e3)));
    EXPECT_TRUE(std::isnan(unconfined_strength_pa(30.0 * deg, std::numeric_limits<double>::quiet_NaN())));
}
