// What the fractions of a grain-size curve count (grain_sizes.hpp): the
// engine's vocabulary, which the job spec reads its
// "specimen.grain_sizes.basis" into directly (api/job_spec.hpp) through
// sieve_basis_names. Apart from grain_sizes.hpp so that the api's headers can
// name it without the distribution.
#pragma once

#include "core/name_table.hpp"

#include <cstdint>
#include <string_view>

namespace wiredem::engine {

/// What the fractions of a size curve count. JSON: "mass", "number".
enum class SieveBasis : std::uint8_t {
    mass,   ///< fraction passing by mass, as a sieve analysis reports it
    number, ///< fraction of the grains by number
};

/// The names of SieveBasis: the job spec's and the engine's.
inline constexpr NameTable<SieveBasis, 2> sieve_basis_names{{
    {"mass", SieveBasis::mass},
    {"number", SieveBasis::number},
}};

[[nodiscard]] constexpr std::string_view to_string(SieveBasis b) noexcept { return name_in(sieve_basis_names, b); }

} // namespace wiredem::engine
