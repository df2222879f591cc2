// The body framing check of each request's headers.
#include "framing.hpp"

#include <boost/beast/core/string.hpp>

namespace wiredem::server {
namespace beast = boost::beast;

std::optional<FramingProblem> framing_problem(const http::fields& headers)
{
    for (const std::string_view name : {"Host", "Origin", "Idempotency-Key"})
        if (headers.count(name) > 1)
            return FramingProblem{http::status::bad_request, "bad_request",
                std::string(name) + " is given more than once"};
    if (const auto expect = headers.find(http::field::expect);
        expect != headers.end() && !beast::iequals(expect->value(), "100-continue"))
        return FramingProblem{http::status::expectation_failed, "expectation_failed",
            "the only expectation served is 100-continue"};
    const auto te = headers.find(http::field::transfer_encoding);
    if (te == headers.end()) return std::nullopt;
    if (headers.find(http::field::content_length) != headers.end())
        return FramingProblem{http::status::bad_request, "bad_request",
            "Transfer-Encoding and Content-Length together are ambiguous framing"};
    const std::string_view codings = te->value();
    std::string_view last = codings.substr(codings.find_last_of(',') == std::string_view::npos
                                               ? 0 : codings.find_last_of(',') + 1);
    const auto trim = [](std::string_view v) {
        while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
        while (!v.empty() && (v.back() == ' ' || v.back() == '\t')) v.remove_suffix(1);
        return v;
    };
    last = trim(last);
    if (!beast::iequals(last, "chunked")) // RFC 9112 §6.3: the length cannot be determined
        return FramingProblem{http::status::bad_request, "bad_request",
            "Transfer-Encoding must end in chunked: the body's framing is unknown"};
    if (!beast::iequals(trim(codings), "chunked"))
        return FramingProblem{http::status::not_implemented, "unsupported_transfer_coding",
            "the only transfer coding served is chunked"};
    return std::nullopt;
}

bool expects_continue(const http::request_header<>& headers)
{
    const auto expect = headers.find(http::field::expect);
    if (expect == headers.end() || headers.version() < 11) return false;
    const bool has_body = headers.find(http::field::transfer_encoding) != headers.end()
                       || (headers.find(http::field::content_length) != headers.end()
                           && headers[http::field::content_length] != "0");
    return has_body && beast::iequals(expect->value(), "100-continue");
}

} // namespace wiredem::server
