// The kinds of wire-deployment pattern (the model spec §5): the engine's
// vocabulary, which the job spec reads its "specimen.wire.pattern" into
// directly (api/job_spec.hpp) through pattern_kind_names. Apart from
// pattern.hpp so that the api's headers can name it without the pattern code
// (and Eigen).
#pragma once

#include "core/name_table.hpp"

#include <string_view>

namespace wiredem::engine {

/// How the nozzle lays the wire. JSON (and pattern_name): "none", "helix",
/// "spiral_helix", "radial_helix", "toolpath".
enum class PatternKind {
    none,          ///< no wire
    helix,         ///< circle of radius R_a rising at v_z
    spiral_helix,  ///< circle of radius R_i whose centre travels on the circle R_a
    radial_helix,  ///< circle R_a with a radial excursion to the axis every φ_rs
    toolpath,      ///< the robot's own path: a polyline per layer (PatternSpec::toolpath)
};

/// The names of PatternKind: the job spec's and the engine's.
inline constexpr NameTable<PatternKind, 5> pattern_kind_names{{
    {"none", PatternKind::none},
    {"helix", PatternKind::helix},
    {"spiral_helix", PatternKind::spiral_helix},
    {"radial_helix", PatternKind::radial_helix},
    {"toolpath", PatternKind::toolpath},
}};

[[nodiscard]] constexpr std::string_view to_string(PatternKind k) noexcept { return name_in(pattern_kind_names, k); }

} // namespace wiredem::engine
