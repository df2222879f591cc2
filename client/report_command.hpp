// `wiredem report OUT/ [-o FILE] [--web-dir DIR]`: one self-contained HTML
// file with the job page's results (summary, warnings, curves, Mohr circles,
// the wire's strain and autocorrelation) for a run's output folder
// (summary.json + result.h5, e.g. `wiredem run` on a cluster node), that opens
// in a browser without a server. The data are the result data routes' own
// shapes (api/result_data.hpp); the drawing code is the web page's
// (web/src/js/results_view.js and its imports, inlined from the installed page).
#pragma once

#include <filesystem>

namespace wiredem::client {

/// Writes `html` (empty: OUT/report.html) from `out_dir`, with the page's
/// files from `web_dir` (empty: share/wiredem/web beside the binary's folder).
/// @return exit_code::ok; throws CommandError(local_io) when a file cannot be
///         read or written
int cmd_report(const std::filesystem::path& out_dir, const std::filesystem::path& html, const std::filesystem::path& web_dir);

} // namespace wiredem::client
