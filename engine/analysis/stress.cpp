// Triaxial measurements; see stress.hpp.
#include "analysis/stress.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace wiredem::engine::analysis {

double axial_strain(double initial_height_m, double height_m) noexcept
{
    return (initial_height_m - height_m) / initial_height_m; // ε_a = (h₀ − h)/h₀
}

double axial_stress_pa(double plate_force_n, double radius_m) noexcept
{
    return plate_force_n / (std::numbers::pi * radius_m * radius_m); // σ₁ = F/(π r²)
}

double effective_confining_pressure_pa(double membrane_normal_force_sum_n, double radius_m, double height_m) noexcept
{
    return membrane_normal_force_sum_n / (2.0 * std::numbers::pi * radius_m * height_m); // ΣF/(2π r h)
}

double effective_confining_pressure_pa(
    std::span<const double> membrane_normal_forces_n, double radius_m, double height_m) noexcept
{
    double sum_n = 0.0;
    for (double f : membrane_normal_forces_n) sum_n += f; // serial, in the caller's order
    return effective_confining_pressure_pa(sum_n, radius_m, height_m);
}

std::optional<double> column_radius_m(
    std::span<const double> contact_radial_distances_m, double grain_radius_m) noexcept
{
    if (contact_radial_distances_m.empty()) return std::nullopt;
    double sum_m = 0.0;
    for (double r : contact_radial_distances_m) sum_m += r;
    return sum_m / static_cast<double>(contact_radial_distances_m.size()) + grain_radius_m;
}

double deviatoric_stress_pa(double sigma1_pa, double sigma3_pa) noexcept { return sigma1_pa - sigma3_pa; }

double stress_ratio(double sigma1_pa, double sigma3_pa) noexcept
{
    const double sum_pa = sigma1_pa + sigma3_pa;
    if (sum_pa == 0.0) return std::numeric_limits<double>::quiet_NaN(); // 0/0 and ±x/0 alike
    return (sigma1_pa - sigma3_pa) / sum_pa;
}

double cylinder_volume_m3(double radius_m, double height_m) noexcept
{
    return std::numbers::pi * radius_m * radius_m * height_m;
}

double volumetric_strain(double initial_volume_m3, double volume_m3) noexcept
{
    return (initial_volume_m3 - volume_m3) / initial_volume_m3; // ε_v = (V₀ − V)/V₀
}

double inertial_number(double strain_rate_per_s, double grain_radius_m, double grain_density_kg_per_m3,
    double confining_pressure_pa) noexcept
{
    // I = ε̇ · d · √(ρ/σ₃) with d = 2 r_p the grain diameter
    return strain_rate_per_s * 2.0 * grain_radius_m * std::sqrt(grain_density_kg_per_m3 / confining_pressure_pa);
}

std::optional<PeakDeviatoricStress> peak_deviatoric_stress(std::span<const double> deviatoric_stress_pa) noexcept
{
    std::optional<PeakDeviatoricStress> peak;
    for (std::size_t i = 0; i < deviatoric_stress_pa.size(); ++i) {
        const double q = deviatoric_stress_pa[i];
        if (std::isnan(q)) continue;
        if (!peak || q > peak->value_pa) peak = PeakDeviatoricStress{q, i};
    }
    return peak;
}

} // namespace wiredem::engine::analysis
