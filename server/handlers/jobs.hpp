// Handlers of the /v1/jobs routes: free functions from (request, services) to
// a response, with no socket in sight (style §7). Path parameters arrive
// decoded; `id` has already passed is_valid_job_id. Each handler is
// thread-safe and never throws (the router catches anything that escapes).
#pragma once

#include "../http.hpp"
#include "../services.hpp"

#include "api/job_spec.hpp"

#include <boost/json/object.hpp>

#include <cstdint>
#include <optional>

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wiredem::server {

/// Decoded query parameters in request order.
using QueryParams = std::vector<std::pair<std::string, std::string>>;

/// Pages of the job and study lists: `limit` by default and at most.
inline constexpr int default_page_size = 50;
inline constexpr int max_page_size = 500;

/// A whole decimal number > 0 (limit, cursor), or nothing.
[[nodiscard]] std::optional<std::int64_t> parse_positive(std::string_view s);

/// POST /v1/jobs: validate the spec, honour Idempotency-Key, queue the job.
/// 201 + Location; 400 invalid_json / invalid_job; 409 idempotency_conflict;
/// 415 when the body is not JSON; 429 + Retry-After when the queue is full.
/// Why this server will not run a valid job: more bodies, time steps or
/// samples than its limits (--max-bodies-per-job, --max-steps-per-job,
/// --max-samples-per-test), with the field that drives the estimate.
[[nodiscard]] std::optional<FieldProblem> job_limit_problem(const api::JobSpec& spec, const ServerConfig& config);

/// Whether the request says its body is application/json (a POST without
/// it is refused: a browser's cross-site Blob POST sends none).
[[nodiscard]] bool is_json_content_type(const Request& req);

/// A job as GET /v1/jobs lists it (live progress, no spec).
[[nodiscard]] boost::json::object job_resource(const JobRecord& r, Services& svc);

[[nodiscard]] Response handle_submit_job(const Request& req, Services& svc);

/// GET /v1/jobs?state=&limit=&cursor=: newest first, `next_cursor` pages on.
[[nodiscard]] Response handle_list_jobs(const Request& req, const QueryParams& params, Services& svc);

/// GET /v1/jobs/{id}: the job with its live progress and its spec.
[[nodiscard]] Response handle_get_job(const Request& req, const std::string& id, Services& svc);

/// DELETE /v1/jobs/{id}: cancels a queued or running job (200 with the job;
/// again for a cancelled one; 409 once it succeeded or failed).
/// DELETE /v1/jobs/{id}?remove=true: removes a job that has ended, with its
/// files (204); 409 for one still active or a study's.
[[nodiscard]] Response handle_delete_job(
    const Request& req, const std::string& id, const QueryParams& params, Services& svc);

/// The retention bound: keeps the --max-finished-jobs most recently ended
/// jobs (a study's excepted); older ones go, with their files.
void apply_retention(Services& svc);

/// GET /v1/jobs/{id}/summary: the runner's summary.json (409 until succeeded).
[[nodiscard]] Response handle_get_summary(const Request& req, const std::string& id, Services& svc);

/// GET /v1/jobs/{id}/result.h5: the HDF5 file, with byte ranges (206, 416)
/// and If-Range; 409 until succeeded.
[[nodiscard]] Response handle_get_result(const Request& req, const std::string& id, Services& svc);

/// The single byte range a Range header asks for, resolved against a size.
struct ByteRange {
    std::uint64_t first = 0;
    std::uint64_t length = 0;
};

/// Result of parsing a Range header: none (send everything), a range, or
/// unsatisfiable (416). Several ranges or a syntax error count as none (RFC 9110 §14.2).
struct RangeRequest {
    enum class Kind { none, range, unsatisfiable } kind = Kind::none;
    ByteRange range;
};

/// Parses `bytes=a-b`, `bytes=a-` and `bytes=-n` against a file of `size` bytes.
[[nodiscard]] RangeRequest parse_range(std::string_view header, std::uint64_t size);

} // namespace wiredem::server
