// Consolidation, a phase of the triaxial test (engine/triaxial/triaxial.hpp):
// while σ₃ ramps up and holds (pressure.hpp), the top plate is the cell's
// loading cap, a piston that comes to rest where σ₁ equals the consolidation
// target; loading then starts from an isotropic state (docs/model.md,
// "Consolidation"). What a series' rows say about the column as loading
// started (LoadingStart) is read here too.
#pragma once

#include "triaxial/consolidation_kind.hpp"
#include "triaxial/sampling.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace wiredem::engine {

/// Consolidation check: loading should start from an isotropic state. A test
/// warns when σ₁ (averaged over the last consolidation window) differs from
/// its consolidation target by more than this fraction when loading starts.
inline constexpr double max_consolidation_mismatch = 0.1;
/// Whether σ₁ [Pa] had consolidated to `target_pa` (within
/// max_consolidation_mismatch): the check behind the test's warning and its
/// `consolidated` verdict. False when either is not finite.
[[nodiscard]] bool within_consolidation_mismatch(double sigma1_pa, double target_pa) noexcept;
/// The hold goes on past hold_time_s (up to max_hold_time_s) until the column
/// has consolidated: σ₁, averaged over a window of this length, within
/// `consolidated_mismatch` of σ₃, and the top plate slower than the loading
/// speed. The window averages out single grain impacts on the plate (one
/// sample of σ₁ scatters by ±6 % at the paper's size, measured).
inline constexpr double consolidation_window_s = 5e-3;
inline constexpr double consolidated_mismatch = 0.05;
/// max_hold_time_s when not given: this many times hold_time_s.
inline constexpr double default_max_hold_factor = 4.0;
/// The top plate moves at most this many times the loading speed while it
/// consolidates the column.
inline constexpr double max_piston_speed_factor = 4.0;

/// The inverse of to_string; nullopt for any other text.
[[nodiscard]] std::optional<Consolidation> consolidation_from_string(std::string_view text) noexcept;

/// The column as loading started, and what the ramp and hold did to it
/// (docs/model.md, "Consolidation"). A column whose membrane squeezes it
/// harder than the piston presses (σ₃,eff above σ₁) can yield in extension
/// while σ₃ is held: it lengthens after its shortest, and loading then
/// starts from η < 0 on a column that has just flowed the other way.
struct LoadingStart {
    std::size_t sample = 0;           ///< the series' first loading row
    /// σ₁ and σ₃,eff averaged over the rows of the last consolidation window
    /// (consolidation_window_s) up to that row, and η of those means.
    double sigma1_pa = 0.0;
    double sigma3_effective_pa = 0.0;
    double stress_ratio = 0.0;
    /// Axial strain of the ramp and hold, (h_first − h)/h_first from the
    /// first row to the loading row: > 0 shortened, < 0 lengthened.
    double axial_strain = 0.0;
    /// How much the column lengthened after its shortest before loading,
    /// (h − h_min)/h_first ≥ 0: the extension flow of the hold.
    double rebound_axial_strain = 0.0;
    /// Radial strain of the ramp and hold, (r_first − r)/r_first (> 0 narrowed).
    double radial_strain = 0.0;
};

/// The mean of `column` (a column of `s`) over the rows up to `last` within
/// consolidation_window_s of it: σ₁ and σ₃,eff as consolidation judges them.
[[nodiscard]] double consolidation_window_mean(const TriaxialSeries& s, const std::vector<double>& column, std::size_t last);

/// The loading start read from a series' rows (the phase column); nullopt
/// when the series has no loading row.
[[nodiscard]] std::optional<LoadingStart> loading_start(const TriaxialSeries& s);

/// The piston's vertical velocity after one step [m/s]: a free body of mass
/// `piston_mass_kg` under the net downward force target − plate force, its
/// speed capped at `max_speed_m_per_s` (a column still settling would throw
/// an uncapped piston). `velocity_m_per_s` is its velocity before the step.
[[nodiscard]] double piston_velocity_m_per_s(double velocity_m_per_s, double target_force_n, double plate_force_n,
    double dt_s, double piston_mass_kg, double max_speed_m_per_s) noexcept;

} // namespace wiredem::engine
