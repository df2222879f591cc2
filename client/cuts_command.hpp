// `wiredem cuts RESULT --count N [--test NAME] [--at-strain E] [--min-spacing-m L]`:
// where to cut the wire so that it loses the least (issue 39): the N places
// of lowest segment strain of a reference test in a result file, at least L
// apart and from the wire's ends (engine::analysis::lowest_strain_cuts), as
// JSON whose cuts_at_m a job takes as specimen.wire.cuts_at_m (docs/client.md).
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

namespace wiredem::client {

/// What `wiredem cuts` is asked.
struct CutsRequest {
    std::filesystem::path result;      ///< result.h5, or the output folder that holds it
    std::string test;                  ///< a test group (sigma3_…) or "free_standing"; empty: the highest pressure
    std::size_t count = 1;             ///< N ≥ 1
    std::optional<double> at_strain;   ///< the snapshot nearest this axial strain; none: nearest the test's peak
    std::optional<double> min_spacing_m; ///< L ≥ 0; none: one loop of the wire about the axis
};

/// Prints {"cuts_at_m": [...], …} for `r`.
/// @return exit_code::ok; throws CommandError(local_io) when the file cannot
///         be read or holds no such test or wire, CommandError(usage) for an
///         argument out of range or no loop length to default to
int cmd_cuts(const CutsRequest& r);

} // namespace wiredem::client
