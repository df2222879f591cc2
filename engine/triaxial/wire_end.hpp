// Which end of the wire a pull-out pulls (pull_out.hpp): the engine's
// vocabulary, which the job spec reads its "free_standing.pull_out_end" into
// directly (api/job_spec.hpp) through wire_end_names. Apart from
// pull_out.hpp so that the api's headers can name it without the driver.
#pragma once

#include "core/name_table.hpp"

#include <cstdint>
#include <string_view>

namespace wiredem::engine {

/// Which end of the wire is pulled. JSON: "last", "first".
enum class WireEnd : std::uint8_t {
    last = 0,  ///< the last node laid: the top end of a printed column
    first = 1, ///< the first node laid: the bottom end
};

/// The names of WireEnd: the job spec's, the engine's and result.h5's.
inline constexpr NameTable<WireEnd, 2> wire_end_names{{
    {"last", WireEnd::last},
    {"first", WireEnd::first},
}};

[[nodiscard]] constexpr std::string_view to_string(WireEnd e) noexcept { return name_in(wire_end_names, e); }

} // namespace wiredem::engine
