// Routing table:
//   POST   /v1/jobs                     GET /v1/jobs
//   GET    /v1/jobs/{id}                DELETE /v1/jobs/{id}
//   GET    /v1/jobs/{id}/summary        GET /v1/jobs/{id}/result.h5
//   GET    /v1/health   /v1/openapi.json   /v1/job-spec/schema   /metrics
//   GET    /v1/jobs/{id}/tests/…, /specimen/…, /result.xdmf, /report.html   (handlers/results.hpp)
//   GET    anything else: the web page's files (handlers/static_files.hpp)
// GET routes also answer HEAD.
#include "router.hpp"

#include "origin.hpp"

#include "handlers/jobs.hpp"
#include "handlers/meta.hpp"
#include "handlers/results.hpp"
#include "handlers/spec_schema.hpp"
#include "handlers/static_files.hpp"
#include "handlers/studies.hpp"

#include <boost/asio/post.hpp>
#include <boost/url/parse.hpp>
#include <boost/url/url_view.hpp>
#include <spdlog/spdlog.h>

#include <string>
#include <vector>

namespace wiredem::server {
namespace {

/// Constant-time comparison: the time taken does not tell how much of a
/// guessed token was right.
bool same_secret(std::string_view given, std::string_view expected)
{
    if (expected.empty()) return false;
    unsigned char diff = given.size() == expected.size() ? 0 : 1;
    for (std::size_t i = 0; i < given.size(); ++i)
        diff |= static_cast<unsigned char>(given[i] ^ expected[i % expected.size()]);
    return diff == 0;
}

bool authorized(const Request& req, const std::string& token)
{
    auto it = req.find(http::field::authorization);
    if (it == req.end()) return false;
    const std::string_view value(it->value().data(), it->value().size());
    constexpr std::string_view scheme = "Bearer ";
    if (value.size() <= scheme.size()) return false;
    std::string prefix(value.substr(0, scheme.size()));
    for (char& c : prefix) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (prefix != "bearer ") return false;
    return same_secret(value.substr(scheme.size()), token);
}

Response method_not_allowed(const Request& req, std::string_view allow)
{
    auto res = error_response(req, http::status::method_not_allowed, "method_not_allowed",
        std::string(req.method_string()) + " is not allowed here (allowed: " + std::string(allow) + ")");
    res.set(http::field::allow, allow);
    return res;
}

std::uint64_t body_bytes(const StringResponse& r) { return r.body().size(); }
std::uint64_t body_bytes(const FileResponse& r) { return r.body().length; }

/// HEAD: the GET reply's headers (Content-Length included) with no body.
void strip_body(Response& res)
{
    std::visit(
        [](auto& r) {
            using T = std::decay_t<decltype(r)>;
            if constexpr (std::is_same_v<T, StringResponse>) {
                r.content_length(r.body().size());
                r.body().clear();
            } else {
                r.content_length(r.body().length);
                r.body().length = 0;
            }
        },
        res);
}

} // namespace

Router::Router(Services& services)
    : svc_(services), submit_pool_(services.config.submit_threads), data_pool_(services.config.data_threads)
{
}

Router::~Router() { stop(); }

void Router::stop() noexcept
{
    submit_pool_.stop();
    data_pool_.stop();
    submit_pool_.join();
    data_pool_.join();
}

Router::Lane Router::lane_of(const Request& req) noexcept
{
    if (req.method() == http::verb::post) return Lane::submit;
    // GET or HEAD /v1/jobs/{id}/{a result data route}/…: what route() sends
    // to handle_result_data (a malformed target or another method is answered
    // at once, on the I/O thread, as before).
    const auto parsed = boost::urls::parse_origin_form(req.target());
    if (!parsed || (req.method() != http::verb::get && req.method() != http::verb::head)) return Lane::io;
    const auto segs = parsed->segments();
    auto it = segs.begin();
    for (std::string_view expected : {"v1", "jobs"}) {
        if (it == segs.end() || *it != expected) return Lane::io;
        ++it;
    }
    if (it == segs.end() || ++it == segs.end()) return Lane::io;
    return is_result_data_route(*it) ? Lane::data : Lane::io;
}

void Router::dispatch_later(std::shared_ptr<const Request> req, std::function<void(std::shared_ptr<Response>)> done) noexcept
{
    if (lane_of(*req) == Lane::data) {
        // No limit of their own: each waits for its connection, which the
        // connection limit bounds, and reads no body.
        boost::asio::post(data_pool_, [this, req = std::move(req), done = std::move(done)] {
            done(std::make_shared<Response>(dispatch(*req)));
        });
        return;
    }
    if (pending_.fetch_add(1) >= svc_.config.max_pending_submits) {
        pending_.fetch_sub(1);
        auto res = error_response(*req, http::status::service_unavailable, "busy",
            "too many submits are being validated; try again shortly");
        res.set(http::field::retry_after, "1");
        svc_.metrics.responses_by_class[5].fetch_add(1, std::memory_order_relaxed);
        done(std::make_shared<Response>(std::move(res)));
        return;
    }
    boost::asio::post(submit_pool_, [this, req = std::move(req), done = std::move(done)] {
        auto res = std::make_shared<Response>(dispatch(*req));
        pending_.fetch_sub(1);
        done(std::move(res));
    });
}

Response Router::dispatch(const Request& req) noexcept
{
    Response res = [&]() -> Response {
        try {
            return route(req);
        } catch (const std::exception& e) {
            spdlog::error("{} {}: {}", std::string(req.method_string()), std::string(req.target()), e.what());
            return error_response(req, http::status::internal_server_error, "internal", e.what());
        } catch (...) {
            return error_response(req, http::status::internal_server_error, "internal", "unknown error");
        }
    }();
    // HEAD: no body on the wire, errors included (routes answered with
    // finish() are stripped already: their body is empty).
    if (req.method() == http::verb::head && std::visit([](const auto& r) { return body_bytes(r) > 0; }, res))
        strip_body(res);
    const unsigned cls = status_of(res) / 100;
    if (cls >= 1 && cls <= 5) svc_.metrics.responses_by_class[cls].fetch_add(1, std::memory_order_relaxed);
    return res;
}

Response Router::route(const Request& req)
{
    auto parsed = boost::urls::parse_origin_form(req.target());
    if (!parsed) { // as documented, a malformed request's connection is closed after the reply
        auto res = error_response(req, http::status::bad_request, "bad_target", "the request target is not a valid path");
        res.keep_alive(false);
        return res;
    }
    const boost::urls::url_view url = *parsed;
    std::vector<std::string> seg;
    for (auto s : url.segments()) seg.push_back(s);

    // The Host must be one of the server's names, and a browser's Origin the
    // server's own (server/origin.hpp): no page of another site reaches it.
    if (const auto host = req.find(http::field::host); host == req.end()) {
        if (req.version() >= 11)
            return error_response(req, http::status::bad_request, "bad_host", "HTTP/1.1 requests must name the Host", "Host");
    } else if (auto problem = host_problem(host->value(), svc_.config)) {
        return error_response(req, http::status::bad_request, "bad_host", *problem, "Host");
    } else if (const auto origin = req.find(http::field::origin); origin != req.end()) {
        if (auto refused = origin_problem(origin->value(), host->value()))
            return error_response(req, http::status::forbidden, "forbidden_origin", *refused, "Origin");
    }

    const bool is_v1 = !seg.empty() && seg[0] == "v1";
    if (is_v1 && !svc_.config.token.empty() && !authorized(req, svc_.config.token)) {
        auto res = error_response(req, http::status::unauthorized, "unauthorized",
            "this server needs 'Authorization: Bearer <token>'");
        res.set(http::field::www_authenticate, "Bearer realm=\"wiredem\"");
        return res;
    }

    const auto method = req.method();
    const bool get = method == http::verb::get || method == http::verb::head;
    auto bad_id = [&] {
        return error_response(req, http::status::bad_request, "bad_id",
            "a job id is " + std::to_string(job_id_length) + " lower-case hex digits", "id");
    };
    auto finish = [&](Response res) {
        if (method == http::verb::head) strip_body(res);
        return res;
    };

    // The result data routes check their own query parameters (max_points).
    if (is_v1 && seg.size() >= 4 && seg[1] == "jobs" && is_result_data_route(seg[3])) {
        if (!is_valid_job_id(seg[2])) return bad_id();
        if (!get) return method_not_allowed(req, "GET, HEAD");
        QueryParams params;
        for (auto p : url.params()) params.emplace_back(p.key, p.has_value ? p.value : std::string());
        return finish(handle_result_data(req, seg, params, svc_));
    }

    // Only the job and study lists take query parameters; elsewhere one is a
    // mistake the client should hear about, not one silently ignored.
    if (!(is_v1 && seg.size() == 2 && (seg[1] == "jobs" || seg[1] == "studies")) && !url.params().empty())
        return error_response(req, http::status::bad_request, "bad_parameter",
            "this route takes no query parameters, got '" + std::string(url.encoded_query()) + "'",
            std::string((*url.params().begin()).key));

    if (seg.size() == 1 && seg[0] == "metrics") {
        if (!get) return method_not_allowed(req, "GET, HEAD");
        return finish(handle_metrics(req, svc_));
    }
    if (!is_v1) {
        if (!get) return method_not_allowed(req, "GET, HEAD");
        return finish(handle_static(req, seg, svc_));
    }
    if (seg.size() < 2) return error_response(req, http::status::not_found, "not_found", "no such route");

    if (seg.size() == 2 && seg[1] == "health") {
        if (!get) return method_not_allowed(req, "GET, HEAD");
        return finish(handle_health(req, svc_));
    }
    if (seg.size() == 2 && seg[1] == "openapi.json") {
        if (!get) return method_not_allowed(req, "GET, HEAD");
        return finish(handle_openapi(req, svc_));
    }
    if (seg.size() == 3 && seg[1] == "job-spec" && seg[2] == "schema") {
        if (!get) return method_not_allowed(req, "GET, HEAD");
        return finish(handle_job_spec_schema(req, svc_));
    }
    if (seg[1] == "studies" && seg.size() <= 4) return finish(route_studies(req, url, seg, method));
    if (seg[1] != "jobs" || seg.size() > 4)
        return error_response(req, http::status::not_found, "not_found", "no such route");

    if (seg.size() == 2) {
        if (method == http::verb::post) return handle_submit_job(req, svc_);
        if (!get) return method_not_allowed(req, "GET, HEAD, POST");
        QueryParams params;
        for (auto p : url.params()) params.emplace_back(p.key, p.has_value ? p.value : std::string());
        return finish(handle_list_jobs(req, params, svc_));
    }

    const std::string& id = seg[2];
    if (id.empty() || (seg.size() == 4 && seg[3] != "summary" && seg[3] != "result.h5"))
        return error_response(req, http::status::not_found, "not_found", "no such route");
    if (!is_valid_job_id(id)) return bad_id();

    if (seg.size() == 3) {
        if (method == http::verb::delete_) return handle_cancel_job(req, id, svc_);
        if (!get) return method_not_allowed(req, "GET, HEAD, DELETE");
        return finish(handle_get_job(req, id, svc_));
    }
    if (!get) return method_not_allowed(req, "GET, HEAD");
    if (seg[3] == "summary") return finish(handle_get_summary(req, id, svc_));
    return finish(handle_get_result(req, id, svc_));
}

Response Router::route_studies(
    const Request& req, const boost::urls::url_view& url, const std::vector<std::string>& seg, http::verb method)
{
    const bool get = method == http::verb::get || method == http::verb::head;
    if (seg.size() == 2) {
        if (method == http::verb::post) return handle_submit_study(req, svc_);
        if (!get) return method_not_allowed(req, "GET, HEAD, POST");
        QueryParams params;
        for (auto p : url.params()) params.emplace_back(p.key, p.has_value ? p.value : std::string());
        return handle_list_studies(req, params, svc_);
    }
    const std::string& id = seg[2];
    if (id.empty() || (seg.size() == 4 && seg[3] != "summary"))
        return error_response(req, http::status::not_found, "not_found", "no such route");
    if (!is_valid_job_id(id))
        return error_response(req, http::status::bad_request, "bad_id",
            "a study id is " + std::to_string(job_id_length) + " lower-case hex digits", "id");
    if (seg.size() == 3) {
        if (method == http::verb::delete_) return handle_cancel_study(req, id, svc_);
        if (!get) return method_not_allowed(req, "GET, HEAD, DELETE");
        return handle_get_study(req, id, svc_);
    }
    if (!get) return method_not_allowed(req, "GET, HEAD");
    return handle_get_study_summary(req, id, svc_);
}

} // namespace wiredem::server
