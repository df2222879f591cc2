// Handlers of the result data routes: what a succeeded job's result.h5 holds,
// read from the file as the runner wrote it (never recomputed), for the web
// page and for scripts that want one column without HDF5:
//
//   GET /v1/jobs/{id}/tests                                  the tests, their columns and snapshots
//   GET /v1/jobs/{id}/tests/{test}/series?max_points=&columns=   time series (JSON)
//   GET /v1/jobs/{id}/specimen                               the prepared specimen's figures and arrays
//   GET /v1/jobs/{id}/specimen/{array}                       one array (binary)
//   GET /v1/jobs/{id}/tests/{test}/snapshots/{k}             a snapshot's figures and arrays
//   GET /v1/jobs/{id}/tests/{test}/snapshots/{k}/{array}     one array (binary)
//   GET /v1/jobs/{id}/tests/{test}/snapshots/{k}/wire_autocorrelation
//   GET /v1/jobs/{id}/free_standing                          the free-standing test: readings, columns, profiles, wire at the peak
//   GET /v1/jobs/{id}/free_standing/series?max_points=&columns=  its time series (JSON)
//   GET /v1/jobs/{id}/free_standing/{snapshots/{k}|peak_snapshot}[/{array}]  its snapshots
//   GET /v1/jobs/{id}/result.xdmf                            the ParaView sidecar
//   GET /v1/jobs/{id}/report.html                            the offline report (api/report.hpp)
//
// {test} is a group name of the file (e.g. "sigma3_20000"), {k} a snapshot
// index; both must exist in the file, so no request names anything else.
//
// While a job prepares or runs, /tests and /tests/{test}/series answer from
// the runner's per-test files instead (campaign::read_test_so_far: a
// finished test's file, a running test's last checkpoint), marked partial,
// with how far each test has reached; so do /free_standing and its series
// (from the runner's tests/free_standing.h5 once the test has finished,
// before that its state); the other routes are 409 until the job has
// succeeded. A job without a free-standing test has no /free_standing (404).
// Arrays are little-endian float32 (positions, forces, strains, radii) or int32
// (indices), row-major, with the shape in `X-Wiredem-Shape: N,3` and the type in
// `X-Wiredem-Dtype`: what a WebGL buffer takes without conversion.
//
// The wire autocorrelation is engine::analysis::autocorrelation of the
// snapshot's stored segment strains with the spec's segment length: the same
// function `wiredem run` took summary.wire.autocorrelation_lag_m and
// autocorrelation_prominent_lag_m from, for the snapshots the summary does not cover.
#pragma once

#include "../http.hpp"
#include "../services.hpp"
#include "jobs.hpp"

#include <boost/json/object.hpp>

#include <string>
#include <vector>

namespace wiredem::server {

/// Whether the fourth path segment of /v1/jobs/{id}/… names a route of this file.
[[nodiscard]] bool is_result_data_route(std::string_view fourth_segment) noexcept;

/// Answers GET /v1/jobs/{id}/{tests|free_standing|specimen|result.xdmf|report.html}/…; `seg` are the
/// decoded path segments ("v1", "jobs", id, …), id already valid. 404 for what
/// the file does not hold, 409 until the job has succeeded (but for the live
/// tests and series), 400 bad_parameter for a query parameter the route does
/// not take or a bad value. Reads HDF5: called on the router's data threads.
[[nodiscard]] Response handle_result_data(
    const Request& req, const std::vector<std::string>& seg, const QueryParams& params, Services& svc);

/// The OpenAPI `paths` of these routes, and the `components` they refer to
/// (merged into GET /v1/openapi.json).
[[nodiscard]] const boost::json::object& result_data_openapi_paths();
[[nodiscard]] const boost::json::object& result_data_openapi_components();

} // namespace wiredem::server
