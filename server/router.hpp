// Maps a request to its handler: parses the target (Boost.URL), checks the
// bearer token on /v1 routes, validates path parameters, answers 404/405 for
// what matches no route, and turns HEAD into GET without a body. Nothing
// crosses the async boundary: every exception becomes a 500.
//
// Thread-safe: dispatch() is called concurrently from every I/O thread.
//
// Submits (POST) validate a job spec, which can take a quarter of a second of
// CPU (the restitution-to-damping fit integrates collisions): they run on the
// router's own submit threads, at most --max-pending-submits waiting, so that
// a flood of submits never holds up the I/O threads that answer status
// requests. The result data routes read HDF5 (a series of a million rows
// takes a second to read and serialise): they run on the data threads
// (--data-threads), for the same reason, apart from the submits.
#pragma once

#include "handlers/jobs.hpp"
#include "http.hpp"
#include "services.hpp"

#include <boost/asio/thread_pool.hpp>

#include <atomic>
#include <functional>
#include <memory>
#include <string_view>
#include <vector>

namespace wiredem::server {

/// What a route's handler gets: the request, the path's id ("" when the
/// path has none; valid when it has one) and the query parameters (only
/// routes that take them see any).
struct RouteCall {
    const Request& req;
    const std::string& id;
    const QueryParams& params;
    Services& svc;
};

/// One operation of the router's table: the table is what the router
/// dispatches by, and what the OpenAPI document is checked against (and
/// completed from: HEAD, operationId, tags, the statuses every route can
/// answer). The result data routes (handlers/results.hpp) and the web
/// page's files are answered before and after it.
struct Route {
    std::string_view path;           ///< OpenAPI path template; "{id}" is a job or study id
    http::verb method;               ///< a GET answers HEAD too
    std::string_view operation_id;   ///< OpenAPI operationId (HEAD: this + "Head")
    std::string_view tag;            ///< OpenAPI tag
    bool takes_query;                ///< the lists' parameters; elsewhere a query is a 400
    Response (*handle)(const RouteCall&);
};

/// Every operation the router dispatches by.
[[nodiscard]] const std::vector<Route>& route_table();

/// The web page's paths as the OpenAPI document names them ("/" and
/// "/{file}", tag "page"): answered after the table, outside /v1, by
/// handle_static (handlers/static_files.hpp); no handler of their own here.
[[nodiscard]] const std::vector<Route>& page_openapi_routes();

/// Dispatches requests to the handlers; holds the services and the submit threads.
class Router {
public:
    explicit Router(Services& services);
    ~Router();
    Router(const Router&) = delete;
    Router& operator=(const Router&) = delete;

    /// The reply to `req`. Never throws; counts the reply in the metrics.
    [[nodiscard]] Response dispatch(const Request& req) noexcept;

    /// Where a request is answered: on the I/O thread that read it, or off
    /// the I/O threads (dispatch_later) on the submit or the data threads.
    enum class Lane { io, submit, data };
    [[nodiscard]] static Lane lane_of(const Request& req) noexcept;

    /// Answers `req` on a thread of its lane and calls `done` there with the
    /// reply. A submit, when --max-pending-submits are already waiting, gets
    /// a 503 (Retry-After) at once. Never throws.
    void dispatch_later(std::shared_ptr<const Request> req, std::function<void(std::shared_ptr<Response>)> done) noexcept;

    /// Stops the submit and data threads (waiting requests are dropped,
    /// running ones finish); call before the I/O threads stop.
    void stop() noexcept;

private:
    Response route(const Request& req);
    Services& svc_;
    boost::asio::thread_pool submit_pool_;
    boost::asio::thread_pool data_pool_;
    std::atomic<std::size_t> pending_{0};  ///< submits waiting or being validated
};

} // namespace wiredem::server
