// HTTP message types shared by the router, the handlers and the session, and
// the helpers that build JSON and error replies. Every reply is JSON except
// /metrics (Prometheus text) and result.h5 (a file range).
//
// Error body: {"error": {"code": "...", "message": "...", "field": "..."|null,
//              "details": [{"field", "message"}]?}}
#pragma once

#include "file_range_body.hpp"

#include <boost/beast/http/empty_body.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/status.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/http/verb.hpp>
#include <boost/json/value.hpp>

#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace wiredem::server {

namespace http = boost::beast::http;

using Request = http::request<http::string_body>;
using StringResponse = http::response<http::string_body>;
using FileResponse = http::response<FileRangeBody>;
/// What a handler returns; the session writes either kind.
using Response = std::variant<StringResponse, FileResponse>;

/// The product name in the Server header.
inline constexpr std::string_view server_name = "wiredem-server/0.1";

/// One problem with one field of a request (the path uses JSON-pointer-like dots).
struct FieldProblem {
    std::string field;
    std::string message;
};

/// A reply with a JSON body; keep-alive and version follow the request.
[[nodiscard]] StringResponse json_response(const Request& req, http::status status, const boost::json::value& body);

/// A reply without a body (204 No Content: a deletion done).
[[nodiscard]] StringResponse no_content_response(const Request& req);

/// A reply with a text body of the given content type.
[[nodiscard]] StringResponse text_response(const Request& req, http::status status, std::string body,
    std::string_view content_type);

/// What an error reply echoes at most: bytes of its message and of each
/// field name (longer ones are cut and say their length), and details.
inline constexpr std::size_t max_error_message_bytes = 1024;
inline constexpr std::size_t max_error_field_bytes = 256;
inline constexpr std::size_t max_error_details = 100;

/// An error reply: `code` is a stable machine-readable word (e.g.
/// "invalid_job"), `message` one human-readable line, `field` the offending
/// field or parameter (empty: none), `details` every problem when there are several.
[[nodiscard]] StringResponse error_response(const Request& req, http::status status, std::string_view code,
    std::string_view message, std::string_view field = {}, const std::vector<FieldProblem>& details = {});

/// Status of a Response of either kind.
[[nodiscard]] unsigned status_of(const Response& res);

} // namespace wiredem::server
