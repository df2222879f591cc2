// What the top plate consolidates the column to (docs/model.md,
// "Consolidation"): the engine's vocabulary, which the job spec reads its
// "triaxial.consolidation" into directly (api/job_spec.hpp) through
// consolidation_names. Apart from consolidation.hpp so that the api's headers
// can name it without the triaxial driver.
#pragma once

#include "core/name_table.hpp"

#include <cstdint>
#include <string_view>

namespace wiredem::engine {

/// What the top plate consolidates the column to while σ₃ ramps and holds.
/// JSON: "cell_pressure", "effective".
enum class Consolidation : std::uint8_t {
    /// σ₁ = σ₃: the cell pressure pushes the cap, as in a laboratory cell. A
    /// stiff membrane squeezes the column harder than that (σ₃,eff > σ₃), and
    /// a column it squeezes to its extension strength flows in extension
    /// while σ₃ is held.
    cell_pressure,
    /// σ₁ = σ₃,eff, the lateral stress the column feels (consolidation_window_mean):
    /// isotropic in the stresses the stress ratio is read from, so loading
    /// starts from η ≈ 0.
    effective,
};

/// The names of Consolidation: the job spec's, the engine's and result.h5's.
inline constexpr NameTable<Consolidation, 2> consolidation_names{{
    {"cell_pressure", Consolidation::cell_pressure},
    {"effective", Consolidation::effective},
}};

[[nodiscard]] constexpr std::string_view to_string(Consolidation c) noexcept { return name_in(consolidation_names, c); }

} // namespace wiredem::engine
