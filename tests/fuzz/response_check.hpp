// What every reply of the router must be, whatever the request: no 500 (an
// exception escaped a handler), a message that serializes and reads back as
// HTTP, a JSON body that is strict JSON (valid UTF-8 included) and, for an
// error, the documented error object; a file reply within the file.
#pragma once

#include "fuzz_check.hpp"

#include "api/json_text.hpp"
#include "http.hpp"

#include <boost/beast/http/parser.hpp>
#include <boost/beast/http/write.hpp>
#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/asio/buffer.hpp>
#include <boost/json.hpp>

#include <sstream>
#include <string>

namespace wiredem::fuzz {

namespace http = server::http;

/// Checks `res`, the reply to a request with method `method`, from a server
/// whose only result file has `file_bytes` bytes.
inline void check_response(const server::Response& res, http::verb method, std::uint64_t file_bytes,
    const std::string& request_text)
{
    const unsigned status = server::status_of(res);
    FUZZ_CHECK(status >= 200 && status < 600 && status != 500, "status " + std::to_string(status) + " for\n" + request_text);
    if (const auto* file = std::get_if<server::FileResponse>(&res)) {
        const auto& b = file->body();
        FUZZ_CHECK(b.offset + b.length <= file_bytes && (method == http::verb::head || b.length > 0),
            "file range " + std::to_string(b.offset) + "+" + std::to_string(b.length) + " for\n" + request_text);
        return;
    }
    const auto& msg = std::get<server::StringResponse>(res);
    std::ostringstream wire;
    wire << msg;
    const std::string text = wire.str();
    // The reply reads back as one HTTP message with the same status and body.
    http::response_parser<http::string_body> parser;
    parser.eager(true);
    if (method == http::verb::head) parser.skip(true);
    boost::beast::error_code ec;
    parser.put(boost::asio::buffer(text), ec);
    if (!ec && !parser.is_done()) parser.put_eof(ec);
    FUZZ_CHECK(!ec && parser.is_done(), "the reply does not read back (" + ec.message() + "):\n" + text);
    FUZZ_CHECK(parser.get().result_int() == status && parser.get().body() == msg.body(), text);

    if (method == http::verb::head || status == 204) {  // 204: a deleted job, no content
        FUZZ_CHECK(msg.body().empty(), "HEAD or 204 reply with a body:\n" + text);
        return;
    }
    const auto ct = msg.find(http::field::content_type);
    FUZZ_CHECK(ct != msg.end(), "reply without Content-Type:\n" + text);
    if (ct->value() != "application/json") return;
    const auto doc = api::parse_json_text(msg.body());
    FUZZ_CHECK(doc.ok(), "the JSON body is not strict JSON (" + (doc.ok() ? std::string() : doc.error()) + "):\n" + text);
    if (status < 400) return;
    const auto* top = doc.value().if_object();
    const auto* err = top && top->contains("error") ? top->at("error").if_object() : nullptr;
    FUZZ_CHECK(err && err->contains("code") && err->at("code").is_string() && err->contains("message")
            && err->at("message").is_string() && err->contains("field")
            && (err->at("field").is_string() || err->at("field").is_null()),
        "not the documented error object:\n" + text);
}

} // namespace wiredem::fuzz
