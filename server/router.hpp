// Maps a request to its handler: parses the target (Boost.URL), checks the
// bearer token on /v1 routes, validates path parameters, answers 404/405 for
// what matches no route, and turns HEAD into GET without a body. Nothing
// crosses the async boundary: every exception becomes a 500.
//
// Thread-safe: dispatch() is called concurrently from every I/O thread.
#pragma once

#include "http.hpp"
#include "services.hpp"

namespace wiredem::server {

/// Dispatches requests to the handlers; holds nothing but the services.
class Router {
public:
    explicit Router(Services& services) : svc_(services) {}

    /// The reply to `req`. Never throws; counts the reply in the metrics.
    [[nodiscard]] Response dispatch(const Request& req) noexcept;

private:
    Response route(const Request& req);
    Services& svc_;
};

} // namespace wiredem::server
