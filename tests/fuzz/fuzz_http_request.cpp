// HTTP request handling without a socket: bytes as a client would send them
// on one connection, parsed as the session parses them (Beast, the server's
// header and body limits, a read buffer of read_buffer_limit bytes, the
// framing check of server/framing.hpp), each
// request answered by the real Router over a real job store
// (server_fixture.hpp). Every reply must pass response_check.hpp; a job the
// server accepts (201) must have the properties of spec_properties.hpp.
#include "response_check.hpp"
#include "server_fixture.hpp"
#include "spec_properties.hpp"

#include "framing.hpp"

#include <boost/beast/http/parser.hpp>

#include <algorithm>
#include <string>

using namespace wiredem;
namespace http = server::http;

namespace {

/// Requests read from one connection at most (pipelining).
constexpr int max_requests = 4;

/// The input with its runs expanded, so that a short input reaches header and
/// trailer fields of 64 KiB and more (where Beast's 16-bit field lengths end)
/// without libFuzzer mutating inputs that long: the marker "\xff\xfe" followed
/// by a byte k stands for 512·k more copies of the byte before the marker.
std::string expand_runs(const std::uint8_t* data, std::size_t size)
{
    std::string out;
    for (std::size_t i = 0; i < size; ++i) {
        if (i + 2 < size && data[i] == 0xff && data[i + 1] == 0xfe && !out.empty()) {
            out.append(std::size_t{512} * data[i + 2], out.back());
            i += 2;
            continue;
        }
        out.push_back(static_cast<char>(data[i]));
    }
    return out;
}

fuzz::ServerFixture& fixture()
{
    static fuzz::ServerFixture f;
    return f;
}

/// A submitted job the server accepted: the spec it was sent is within limits.
void check_accepted_submit(const server::Request& req)
{
    const auto spec = api::parse_job_spec(std::string_view(req.body()));
    FUZZ_CHECK(spec.ok(), "201 for a spec the parser rejects: " + req.body());
    const auto& cfg = fixture().config();
    fuzz::check_parsed_spec(spec.value());
    fuzz::check_served_spec(spec.value(), {static_cast<double>(cfg.max_bodies_per_job), cfg.max_steps_per_job,
                                               cfg.max_samples_per_test});
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    auto& f = fixture();
    f.restore();  // an earlier input may have deleted a job
    const std::string input = expand_runs(data, size);
    boost::asio::const_buffer rest(input.data(), input.size());
    // The session's read buffer holds at most this many bytes that the parser
    // has not consumed; a parser that needs more ends the read with
    // buffer_overflow (a 431 and a closed connection).
    const std::size_t buffer_limit = server::read_buffer_limit(f.config().max_header_bytes);
    for (int n = 0; n < max_requests && rest.size() > 0; ++n) {
        http::request_parser<http::string_body> parser;
        parser.header_limit(f.config().max_header_bytes);
        parser.body_limit(f.config().max_body_bytes);
        boost::beast::error_code ec;
        // The headers first, as the session reads them (async_read_header).
        // need_more: the input ends inside them, and the session would wait
        // for the rest until its read timeout.
        const auto feed = [&](auto done) {
            while (!ec && !done() && rest.size() > 0) {
                const boost::asio::const_buffer window(rest.data(), std::min(rest.size(), buffer_limit));
                const std::size_t used = parser.put(window, ec);
                rest += used;
                if (used == 0 && !ec) {
                    if (window.size() == buffer_limit) ec = http::error::buffer_overflow;
                    break;
                }
            }
        };
        feed([&] { return parser.is_header_done(); });
        if (ec || !parser.is_header_done()) return 0;  // a 4xx and a closed connection, or still waiting
        if (server::framing_problem(parser.get())) return 0;  // refused before the body is read
        parser.eager(true);
        feed([&] { return parser.is_done(); });
        if (ec == http::error::need_more) ec = {};
        if (!ec && !parser.is_done()) parser.put_eof(ec);  // the client closed the connection
        if (ec || !parser.is_done()) return 0;
        const server::Request req = parser.release();
        const std::string request_text = [&] {
            std::ostringstream s;
            s << req;
            return s.str();
        }();
        // POSTs run on a submit thread in the server; the same dispatch().
        const server::Response res = f.router().dispatch(req);
        fuzz::check_response(res, req.method(), fuzz::result_bytes, request_text);
        if (req.method() == http::verb::post && server::status_of(res) == 201) check_accepted_submit(req);
        const bool keep_alive = std::visit([](const auto& r) { return r.keep_alive(); }, res);
        if (!keep_alive) break;
    }
    return 0;
}
