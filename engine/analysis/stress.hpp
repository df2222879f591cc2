// The triaxial measurements of the model spec §6.3 as small pure functions:
// numbers in, numbers out, SI units in every name. Compression is positive for
// stresses and strains (a shortening column has ε_a > 0, a shrinking one ε_v > 0).
// They do not validate: a zero area or volume gives ±inf or NaN as IEEE arithmetic
// does, except where a doc comment says otherwise. Thread safe.
#pragma once

#include <cstddef>
#include <optional>
#include <span>

namespace wiredem::engine::analysis {

/// Axial strain ε_a = (h₀ − h)/h₀ from the plate distance.
/// @param initial_height_m  h₀, plate distance when loading starts [m], > 0
/// @param height_m          h, current plate distance [m]
[[nodiscard]] double axial_strain(double initial_height_m, double height_m) noexcept;

/// Axial stress σ₁ = F / (π r²) [Pa].
/// @param plate_force_n  vertical force on the plate, pushing into the column [N]
/// @param radius_m       column radius r [m], > 0
[[nodiscard]] double axial_stress_pa(double plate_force_n, double radius_m) noexcept;

/// Effective confining pressure σ₃,eff = Σ F_n / (2π r h) [Pa]: the normal
/// forces of the specimen's (grains' and wire's) contacts with the membrane
/// spread over the lateral area in contact.
/// @param membrane_normal_force_sum_n  Σ of those normal force magnitudes [N]
/// @param radius_m                     column radius r [m], > 0
/// @param height_m                     plate distance h [m], > 0
[[nodiscard]] double effective_confining_pressure_pa(
    double membrane_normal_force_sum_n, double radius_m, double height_m) noexcept;

/// As above, summing the individual contact force magnitudes [N] in the given order
/// (pass them in canonical contact order for a bit-reproducible result).
[[nodiscard]] double effective_confining_pressure_pa(
    std::span<const double> membrane_normal_forces_n, double radius_m, double height_m) noexcept;

/// Column radius: the mean radial distance of the grain centres touching the membrane
/// plus the grain radius r_p [m] (the model spec §6.3). Empty without contacts.
/// @param contact_radial_distances_m  √(x² + y²) of each grain centre in contact [m]
/// @param grain_radius_m              r_p [m]
[[nodiscard]] std::optional<double> column_radius_m(
    std::span<const double> contact_radial_distances_m, double grain_radius_m) noexcept;

/// Deviatoric stress q = σ₁ − σ₃ [Pa].
[[nodiscard]] double deviatoric_stress_pa(double sigma1_pa, double sigma3_pa) noexcept;

/// Stress ratio (σ₁ − σ₃)/(σ₁ + σ₃), dimensionless; NaN when σ₁ + σ₃ = 0.
[[nodiscard]] double stress_ratio(double sigma1_pa, double sigma3_pa) noexcept;

/// Volume of a cylinder π r² h [m³].
[[nodiscard]] double cylinder_volume_m3(double radius_m, double height_m) noexcept;

/// Volumetric strain ε_v = (V₀ − V)/V₀, positive when the specimen contracts.
/// @param initial_volume_m3  V₀ [m³], > 0
/// @param volume_m3          V [m³]
[[nodiscard]] double volumetric_strain(double initial_volume_m3, double volume_m3) noexcept;

/// Inertial number I = ε̇ · 2 r_p · √(ρ_p / σ₃) (the model spec §4); I ≲ 10⁻³ is
/// usually taken as quasi-static. Infinite for σ₃ = 0 and ε̇ > 0.
/// @param strain_rate_per_s       ε̇ = v_z / h₀ [1/s], ≥ 0
/// @param grain_radius_m          r_p [m]
/// @param grain_density_kg_per_m3 ρ_p [kg/m³]; pass the scaled density under mass scaling
/// @param confining_pressure_pa   σ₃ [Pa], ≥ 0
[[nodiscard]] double inertial_number(double strain_rate_per_s, double grain_radius_m, double grain_density_kg_per_m3,
    double confining_pressure_pa) noexcept;

/// The largest deviatoric stress of a test and the sample it occurred at.
struct PeakDeviatoricStress {
    double value_pa = 0.0; ///< max q [Pa]
    std::size_t index = 0; ///< sample index of the first occurrence of the maximum
};

/// Peak of a deviatoric-stress time series (the yield strength, the model spec §6.4).
/// NaN samples are skipped; the first of equal maxima wins. Empty when the series is
/// empty or has no non-NaN sample.
[[nodiscard]] std::optional<PeakDeviatoricStress> peak_deviatoric_stress(
    std::span<const double> deviatoric_stress_pa) noexcept;

} // namespace wiredem::engine::analysis
