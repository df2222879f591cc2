// Handlers of the routes about the service itself: health, metrics and the
// OpenAPI description. Thread-safe, never throw on their own.
#pragma once

#include "../http.hpp"
#include "../services.hpp"

namespace wiredem::server {

/// GET /v1/health: {"status": "ok", …} with queue and worker counts.
[[nodiscard]] Response handle_health(const Request& req, Services& svc);

/// GET /metrics: Prometheus text exposition format 0.0.4.
[[nodiscard]] Response handle_metrics(const Request& req, Services& svc);

/// GET /v1/openapi.json: this API as an OpenAPI 3.0 document.
[[nodiscard]] Response handle_openapi(const Request& req, Services& svc);

/// The OpenAPI document itself (also checked by the tests).
[[nodiscard]] const boost::json::value& openapi_document();

} // namespace wiredem::server
