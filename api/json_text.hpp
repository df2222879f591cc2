// Strict JSON text parsing for the job spec: RFC 8259 only (no comments, no
// trailing commas, valid UTF-8), no duplicate keys, and numbers converted with
// correct rounding (Boost.JSON 1.81's own conversion can be one ulp off, which
// would break the text round trip client → server of a spec).
//
// Errors carry the parser's message and the position of the problem.
#pragma once

#include "core/result.hpp"

#include <boost/json/value.hpp>

#include <cmath>
#include <string>
#include <string_view>

namespace wiredem::api {

/// Parses one JSON document. Whitespace may surround it; anything else after
/// it is an error. Every floating-point number is the double nearest to its
/// text (std::from_chars); integers that fit become int64 (or uint64 above
/// INT64_MAX). Thread-safe (no shared state).
/// @return the document, or a message such as
///         `syntax error at line 3, column 7 (byte 41)` or
///         `duplicate key "seed" at line 1, column 19 (byte 18)`
[[nodiscard]] engine::Result<boost::json::value, std::string> parse_json_text(std::string_view text);

/// A double as JSON: the number, or null when it is not finite. JSON has no
/// NaN or infinity, and Boost.JSON would write them as text that no parser
/// reads; every result document writes its figures through this.
[[nodiscard]] inline boost::json::value finite_or_null(double x)
{
    return std::isfinite(x) ? boost::json::value(x) : boost::json::value(nullptr);
}

/// A document as JSON text, every number that is not finite written as null:
/// what wiredem writes for others to read (summary.json, the server's
/// responses, the command line's JSON) goes through this, so a NaN that
/// reached any field still gives a text that parsers read.
[[nodiscard]] std::string json_document_text(const boost::json::value& document);

} // namespace wiredem::api
