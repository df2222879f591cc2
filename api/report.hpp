// The offline report: one self-contained HTML file with a job's results
// (summary, warnings, curves, Mohr circles, the wire's strain and its
// autocorrelation, the free-standing test's stress–strain curve, radius
// profiles and wire tension) that opens in a browser without a server. The data are the
// result data routes' own shapes (api/result_data.hpp); the drawing code is
// the web page's (web/src/js/results_view.js and its imports, read from the
// installed page and inlined). Written by `wiredem report OUT/` and served by
// GET /v1/jobs/{id}/report.html.
#pragma once

#include <filesystem>
#include <string>

namespace wiredem::api {

/// The report of a run's summary.json and result.h5, with the page's files
/// from `web_dir` (share/wiredem/web); `source` says where the results came
/// from. @throws std::runtime_error (engine::io::Hdf5Error for the HDF5 file)
/// when a file cannot be read.
[[nodiscard]] std::string report_html(const std::filesystem::path& summary_json, const std::filesystem::path& result_h5,
    const std::filesystem::path& web_dir, const std::string& source);

} // namespace wiredem::api
