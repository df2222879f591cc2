// Routing: the result data routes, GET /v1/jobs/{id}/tests/…, /specimen/…,
// /result.xdmf, /report.html (handlers/results.hpp); then route_table(); then,
// outside /v1, the web page's files (handlers/static_files.hpp). GET routes
// also answer HEAD.
#include "router.hpp"

#include "origin.hpp"

#include "io/atomic_file.hpp"

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

Response bad_id_response(const Request& req, std::string_view what)
{
    return error_response(req, http::status::bad_request, "bad_id",
        "a " + std::string(what) + " id is " + std::to_string(job_id_length) + " lower-case hex digits", "id");
}

/// Whether the path's segments fit `tmpl` ("/v1/jobs/{id}"); `id` gets the
/// segment at "{id}" (any non-empty one: the caller checks it).
bool path_matches(std::string_view tmpl, const std::vector<std::string>& seg, std::string& id)
{
    std::size_t k = 0;
    while (!tmpl.empty()) {
        tmpl.remove_prefix(1);  // the '/'
        const std::string_view part = tmpl.substr(0, tmpl.find('/'));
        tmpl.remove_prefix(part.size());
        if (k >= seg.size()) return false;
        if (part == "{id}") {
            if (seg[k].empty()) return false;
            id = seg[k];
        } else if (seg[k] != part) {
            return false;
        }
        ++k;
    }
    return k == seg.size();
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

const std::vector<Route>& route_table()
{
    using V = http::verb;
    // GET before the other methods of a path: the order of Allow.
    static const std::vector<Route> table{
        {"/v1/jobs", V::get, "listJobs", "jobs", true,
            [](const RouteCall& c) { return handle_list_jobs(c.req, c.params, c.svc); }},
        {"/v1/jobs", V::post, "submitJob", "jobs", false, [](const RouteCall& c) { return handle_submit_job(c.req, c.svc); }},
        {"/v1/jobs/{id}", V::get, "getJob", "jobs", false,
            [](const RouteCall& c) { return handle_get_job(c.req, c.id, c.svc); }},
        {"/v1/jobs/{id}", V::delete_, "deleteJob", "jobs", true,
            [](const RouteCall& c) { return handle_delete_job(c.req, c.id, c.params, c.svc); }},
        {"/v1/jobs/{id}/summary", V::get, "getJobSummary", "results", false,
            [](const RouteCall& c) { return handle_get_summary(c.req, c.id, c.svc); }},
        {"/v1/jobs/{id}/result.h5", V::get, "getJobResult", "results", false,
            [](const RouteCall& c) { return handle_get_result(c.req, c.id, c.svc); }},
        {"/v1/studies", V::get, "listStudies", "studies", true,
            [](const RouteCall& c) { return handle_list_studies(c.req, c.params, c.svc); }},
        {"/v1/studies", V::post, "submitStudy", "studies", false,
            [](const RouteCall& c) { return handle_submit_study(c.req, c.svc); }},
        {"/v1/studies/{id}", V::get, "getStudy", "studies", false,
            [](const RouteCall& c) { return handle_get_study(c.req, c.id, c.svc); }},
        {"/v1/studies/{id}", V::delete_, "deleteStudy", "studies", true,
            [](const RouteCall& c) { return handle_delete_study(c.req, c.id, c.params, c.svc); }},
        {"/v1/studies/{id}/summary", V::get, "getStudySummary", "studies", false,
            [](const RouteCall& c) { return handle_get_study_summary(c.req, c.id, c.svc); }},
        {"/v1/health", V::get, "getHealth", "service", false, [](const RouteCall& c) { return handle_health(c.req, c.svc); }},
        {"/v1/openapi.json", V::get, "getOpenApi", "service", false,
            [](const RouteCall& c) { return handle_openapi(c.req, c.svc); }},
        {"/v1/job-spec/schema", V::get, "getJobSpecSchema", "service", false,
            [](const RouteCall& c) { return handle_job_spec_schema(c.req, c.svc); }},
        {"/metrics", V::get, "getMetrics", "service", false, [](const RouteCall& c) { return handle_metrics(c.req, c.svc); }},
    };
    return table;
}

const std::vector<Route>& page_openapi_routes()
{
    static const std::vector<Route> pages{{"/", http::verb::get, "getPage", "page", false, nullptr},
        {"/{file}", http::verb::get, "getPageFile", "page", false, nullptr}};
    return pages;
}

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
        } catch (const engine::io::WriteError& e) {
            // A full disk (the store's or a job folder's) passes once space is
            // freed: 507, with when to try again, not a 500.
            spdlog::error("{} {}: {}", std::string(req.method_string()), std::string(req.target()), e.what());
            if (!e.no_space()) return error_response(req, http::status::internal_server_error, "internal", e.what());
            auto res = error_response(req, http::status::insufficient_storage, "insufficient_storage",
                "the server's disk is full (" + std::string(e.what()) + "); try again once space is freed");
            res.set(http::field::retry_after, std::to_string(svc_.config.retry_after.count()));
            return res;
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
    auto finish = [&](Response res) {
        if (method == http::verb::head) strip_body(res);
        return res;
    };
    QueryParams params;
    for (auto p : url.params()) params.emplace_back(p.key, p.has_value ? p.value : std::string());
    // Only the job and study lists take query parameters (and the result
    // data routes theirs); elsewhere one is a mistake the client should hear
    // about, not one silently ignored.
    auto query_refused = [&] {
        return error_response(req, http::status::bad_request, "bad_parameter",
            "this route takes no query parameters, got '" + std::string(url.encoded_query()) + "'", params.front().first);
    };

    // The result data routes check their own query parameters (max_points).
    if (is_v1 && seg.size() >= 4 && seg[1] == "jobs" && is_result_data_route(seg[3])) {
        if (!is_valid_job_id(seg[2])) return bad_id_response(req, "job");
        if (!get) return method_not_allowed(req, "GET, HEAD");
        return finish(handle_result_data(req, seg, params, svc_));
    }

    // The table: the path first (its id checked), then the method.
    std::string id;
    const Route* op = nullptr;
    std::string allow;
    std::string_view matched_path;
    for (const Route& r : route_table()) {
        if (!path_matches(r.path, seg, id)) continue;
        matched_path = r.path;
        allow += (allow.empty() ? "" : ", ") + std::string(http::to_string(r.method));
        if (r.method == http::verb::get) allow += ", HEAD";
        if (r.method == method || (r.method == http::verb::get && get)) op = &r;
    }
    if (matched_path.empty()) {
        if (is_v1) return error_response(req, http::status::not_found, "not_found", "no such route");
        if (!params.empty()) return query_refused();
        if (!get) return method_not_allowed(req, "GET, HEAD");
        return finish(handle_static(req, seg, svc_));
    }
    if (matched_path.find("{id}") != std::string_view::npos && !is_valid_job_id(id))
        return bad_id_response(req, matched_path.substr(0, 11) == "/v1/studies" ? "study" : "job");
    if (!op) return method_not_allowed(req, allow);
    if (!params.empty() && !op->takes_query) return query_refused();
    return finish(op->handle(RouteCall{req, id, params, svc_}));
}

} // namespace wiredem::server
