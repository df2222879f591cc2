// Triaxial measurement helpers (the model spec §6.3) against hand-computed values.
#include "analysis/stress.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

using namespace wiredem::engine::analysis;

TEST(AxialStrain, IsRelativeShorteningOfThePlateDistance)
{
    EXPECT_NEAR(axial_strain(0.12, 0.108), 0.1, 1e-15);
    EXPECT_EQ(axial_strain(0.12, 0.12), 0.0);
}

TEST(AxialStress, IsPlateForceOverCrossSection)
{
    // 100 N on a 20 mm radius: 100 / (π · 4e-4) = 79577.4715 Pa
    EXPECT_NEAR(axial_stress_pa(100.0, 0.02), 79577.47154594767, 1e-8);
}

TEST(EffectiveConfiningPressure, IsMembraneForceOverLateralContactArea)
{
    // 50 N over 2π · 0.02 m · 0.1 m = 0.012566 m²: 3978.8736 Pa
    EXPECT_NEAR(effective_confining_pressure_pa(50.0, 0.02, 0.1), 3978.873577297384, 1e-9);
    const std::vector<double> contact_forces_n = {10.0, 15.0, 25.0};
    EXPECT_DOUBLE_EQ(effective_confining_pressure_pa(contact_forces_n, 0.02, 0.1),
        effective_confining_pressure_pa(50.0, 0.02, 0.1));
}

TEST(ColumnRadius, IsMeanContactRadialDistancePlusGrainRadius)
{
    const std::vector<double> radial_m = {0.0180, 0.0185};
    const auto r = column_radius_m(radial_m, 1.23e-3);
    ASSERT_TRUE(r.has_value());
    EXPECT_NEAR(*r, 0.01825 + 0.00123, 1e-15);
    EXPECT_FALSE(column_radius_m(std::vector<double>{}, 1.23e-3).has_value());
}

TEST(DeviatoricStress, IsAxialMinusConfining)
{
    EXPECT_EQ(deviatoric_stress_pa(300e3, 100e3), 200e3);
}

TEST(StressRatio, IsDeviatoricOverSumAndNaNWhenUnloaded)
{
    EXPECT_DOUBLE_EQ(stress_ratio(300e3, 100e3), 0.5);
    EXPECT_TRUE(std::isnan(stress_ratio(0.0, 0.0)));
    EXPECT_TRUE(std::isnan(stress_ratio(1e3, -1e3)));
}

TEST(VolumetricStrain, IsRelativeVolumeLossOfTheCylinder)
{
    const double v0 = cylinder_volume_m3(0.02, 0.10);
    const double v = cylinder_volume_m3(0.021, 0.09);
    EXPECT_NEAR(v0, std::numbers::pi * 4e-5, 1e-18);
    // 1 − (0.021² · 0.09)/(0.02² · 0.10) = 1 − 1.1025 · 0.9 = 0.00775
    EXPECT_NEAR(volumetric_strain(v0, v), 0.00775, 1e-13);
}

TEST(InertialNumber, IsStrainRateTimesDiameterTimesRootOfDensityOverPressure)
{
    // paper loading: 0.2 mm/s on a 0.12 m column, r_p = 1.23 mm, ρ = 7800, σ₃ = 100 kPa
    const double rate_per_s = 0.2e-3 / 0.12;
    const double expected = rate_per_s * 2.46e-3 * std::sqrt(7800.0 / 1e5); // ≈ 1.14507e-6
    EXPECT_NEAR(inertial_number(rate_per_s, 1.23e-3, 7800.0, 1e5), expected, 1e-20);
    EXPECT_NEAR(expected, 1.14507e-6, 1e-10);
    EXPECT_TRUE(std::isinf(inertial_number(rate_per_s, 1.23e-3, 7800.0, 0.0)));
}

TEST(PeakDeviatoricStress, IsFirstLargestSampleIgnoringNaN)
{
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<double> q_pa = {nan, 1e3, 5e3, 3e3, 5e3, nan, 2e3};
    const auto peak = peak_deviatoric_stress(q_pa);
    ASSERT_TRUE(peak.has_value());
    EXPECT_EQ(peak->value_pa, 5e3);
    EXPECT_EQ(peak->index, 2u);
    EXPECT_FALSE(peak_deviatoric_stress(std::vector<double>{}).has_value());
    EXPECT_FALSE(peak_deviatoric_stress(std::vector<double>{nan, nan}).has_value());
}
