// `wiredem autocorrelation RESULT.h5 [--test NAME] [--snapshot K]`: the
// autocorrelation of a snapshot's wire segment strains, as the server's
// GET …/snapshots/{k}/wire_autocorrelation answers it (api::wire_autocorrelation_json,
// engine::analysis::autocorrelation, with the job's segment length), for a
// result file without a server: what the Python package (python/wiredem)
// reads R(lag) of a file through, so that no second implementation exists.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace wiredem::client {

/// Prints the JSON object of test `test` (empty: the highest pressure, whose
/// last snapshot summary.json's wire lags are read at) and snapshot `snapshot`
/// (none: its last) of `result_h5`.
/// @return exit_code::ok; throws CommandError(local_io) when the file cannot be
///         read or holds no such test, snapshot or wire
int cmd_autocorrelation(const std::filesystem::path& result_h5, const std::string& test,
    std::optional<long long> snapshot);

} // namespace wiredem::client
