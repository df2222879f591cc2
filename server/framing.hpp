// Whether a request's body framing can be trusted (RFC 9112 §6), and its
// headers are otherwise sound: checked on the headers, before the body is read. Beast frames a request with, say,
// `Transfer-Encoding: gzip` as having no body, and what the client meant as
// the body would then be read as the next request (smuggling). A pure
// function of the headers, so that the HTTP fuzz target runs the session's
// check with no socket (tests/fuzz/fuzz_http_request.cpp).
#pragma once

#include "http.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace wiredem::server {

/// The largest `--max-header-bytes`. Beast's fields store a field's name and
/// value with 16-bit lengths and throw std::length_error, from inside the
/// parser, for a value of 65 534 bytes or more. The session's read buffer holds
/// at most the header limit (read_buffer_limit), and a field has to fit in it
/// with its name, so below this limit no field can reach that size.
inline constexpr std::uint32_t max_header_bytes_limit = 65535;

/// The most bytes a session's read buffer holds: the header limit. A request's
/// headers, each chunk-size line of a chunked body and its trailer must fit in
/// it, so a trailer is bounded like the headers (Beast bounds only the
/// headers): a larger one ends the read with http::error::buffer_overflow,
/// answered 431 like headers over the limit.
[[nodiscard]] constexpr std::size_t read_buffer_limit(std::uint32_t max_header_bytes) noexcept
{
    return max_header_bytes;
}

/// Why a request's framing is refused: the reply to send before closing.
struct FramingProblem {
    http::status status;
    std::string_view code;
    std::string message;
};

/// A problem when the body would be framed by anything but a single
/// `chunked` coding, or by Transfer-Encoding and Content-Length together;
/// when a header that must be single (Host, RFC 9112 §3.2; Origin and
/// Idempotency-Key, which the router reads once) comes twice (400: which
/// one is meant?); when an Expect asks for anything but 100-continue (417);
/// nullopt when the headers are sound.
[[nodiscard]] std::optional<FramingProblem> framing_problem(const http::fields& headers);

/// Whether the client waits for "100 Continue" before it sends the body
/// (Expect: 100-continue, RFC 9110 §10.1.1, on an HTTP/1.1 request with a
/// body): the session sends it once the headers have passed framing_problem.
[[nodiscard]] bool expects_continue(const http::request_header<>& headers);

} // namespace wiredem::server
