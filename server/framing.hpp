// Whether a request's body framing can be trusted (RFC 9112 §6): checked on
// the headers, before the body is read. Beast frames a request with, say,
// `Transfer-Encoding: gzip` as having no body, and what the client meant as
// the body would then be read as the next request (smuggling). A pure
// function of the headers, so that the HTTP fuzz target runs the session's
// check with no socket (tests/fuzz/fuzz_http_request.cpp).
#pragma once

#include "http.hpp"

#include <optional>
#include <string>
#include <string_view>

namespace wiredem::server {

/// Why a request's framing is refused: the reply to send before closing.
struct FramingProblem {
    http::status status;
    std::string_view code;
    std::string message;
};

/// A problem when the body would be framed by anything but a single
/// `chunked` coding, or by Transfer-Encoding and Content-Length together;
/// nullopt when the framing is sound.
[[nodiscard]] std::optional<FramingProblem> framing_problem(const http::fields& headers);

} // namespace wiredem::server
