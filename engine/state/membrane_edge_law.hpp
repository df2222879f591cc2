// How a membrane edge acts when shorter than its rest length: the engine's
// vocabulary, which the job spec reads its "specimen.membrane.edges" into
// directly (api/job_spec.hpp) through membrane_edge_law_names. Apart from
// membrane.hpp so that the api's headers can name it without the mesh.
#pragma once

#include "core/name_table.hpp"

#include <cstdint>
#include <string_view>

namespace wiredem::engine {

/// How a membrane edge responds when it is shorter than its rest length.
/// JSON: "tension_only", "linear".
enum class MembraneEdgeLaw : std::uint8_t {
    /// A thin sheet wrinkles rather than carry compression: an edge pulls when
    /// stretched and is slack when shorter than its rest length. The default:
    /// with linear edges the contracted membrane holds up part of σ₃ by hoop
    /// compression, and the grains feel less than the applied pressure
    /// (docs/model.md, "The membrane carries no compression").
    tension_only,
    /// The model spec §3 as written: a linear spring in tension and compression.
    linear,
};

/// The names of MembraneEdgeLaw: the job spec's and the engine's.
inline constexpr NameTable<MembraneEdgeLaw, 2> membrane_edge_law_names{{
    {"tension_only", MembraneEdgeLaw::tension_only},
    {"linear", MembraneEdgeLaw::linear},
}};

[[nodiscard]] constexpr std::string_view to_string(MembraneEdgeLaw e) noexcept
{
    return name_in(membrane_edge_law_names, e);
}

} // namespace wiredem::engine
