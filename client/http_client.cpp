// Blocking calls built from Beast's asynchronous operations, because only
// those honour tcp_stream deadlines: start the operation, run the
// io_context until it completes, return its error code.
#include "http_client.hpp"

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/buffer_body.hpp>
#include <boost/beast/http/error.hpp>
#include <boost/beast/http/parser.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/http/write.hpp>
#include <boost/url/parse.hpp>
#include <boost/url/url_view.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

namespace wiredem::client {
namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

namespace {

constexpr std::uint64_t max_reply_bytes = 64u << 20;
constexpr std::string_view user_agent = "wiredem-client/0.1";

std::string lower(std::string s)
{
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

template <class Fields>
std::map<std::string, std::string> header_map(const Fields& fields)
{
    std::map<std::string, std::string> out;
    for (const auto& f : fields) out[lower(std::string(f.name_string()))] = std::string(f.value());
    return out;
}

http::verb to_verb(Method m)
{
    switch (m) {
    case Method::get: return http::verb::get;
    case Method::head: return http::verb::head;
    case Method::post: return http::verb::post;
    case Method::del: return http::verb::delete_;
    }
    return http::verb::get;
}

bool is_connection_closed(const beast::error_code& ec)
{
    return ec == http::error::end_of_stream || ec == asio::error::eof || ec == asio::error::connection_reset
        || ec == asio::error::broken_pipe || ec == http::error::partial_message;
}

} // namespace

ServerUrl parse_server_url(std::string_view text)
{
    auto fail = [&](const std::string& why) -> CommandError {
        return CommandError(exit_code::usage, "bad server URL '" + std::string(text) + "': " + why);
    };
    auto parsed = boost::urls::parse_uri(text);
    if (!parsed) throw fail("expected http://HOST[:PORT][/PREFIX]");
    const boost::urls::url_view url = *parsed;
    if (lower(std::string(url.scheme())) != "http")
        throw fail(url.scheme() == "https" ? "https is not supported; reach the server over http (e.g. through an SSH tunnel)"
                                           : "the scheme must be http");
    if (url.has_userinfo() || url.has_query() || url.has_fragment())
        throw fail("no user, query or fragment allowed");
    ServerUrl s;
    s.host = std::string(url.encoded_host());
    if (s.host.size() >= 2 && s.host.front() == '[') s.host = s.host.substr(1, s.host.size() - 2);
    if (s.host.empty()) throw fail("no host");
    s.port = url.has_port() ? std::string(url.port()) : "80";
    if (s.port.empty()) throw fail("empty port");
    s.base_path = std::string(url.encoded_path());
    while (!s.base_path.empty() && s.base_path.back() == '/') s.base_path.pop_back();
    s.text = std::string(text);
    return s;
}

std::string HttpReply::header(const std::string& name) const
{
    auto it = headers.find(name);
    return it == headers.end() ? std::string() : it->second;
}

struct HttpClient::Impl {
    ServerUrl server;
    std::string token;
    std::chrono::milliseconds timeout;
    asio::io_context ioc;
    beast::tcp_stream stream{ioc};
    beast::flat_buffer buffer;
    bool connected = false;

    /// Runs one asynchronous operation to completion. `start` receives a
    /// completion handler taking (error_code, anything…).
    template <class Start>
    beast::error_code run(Start&& start)
    {
        beast::error_code result = asio::error::would_block;
        start([&result](beast::error_code ec, auto&&...) { result = ec; });
        ioc.restart();
        ioc.run();
        return result;
    }

    [[noreturn]] void network_error(const std::string& what, const beast::error_code& ec)
    {
        close();
        const std::string why = ec == beast::error::timeout
            ? "timed out after " + std::to_string(timeout.count() / 1000.0).substr(0, 4) + " s"
            : ec.message();
        throw CommandError(exit_code::network, what + " " + server.text + ": " + why);
    }

    void close()
    {
        beast::error_code ignored;
        stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
        stream.close();
        buffer.clear();
        connected = false;
    }

    void connect()
    {
        tcp::resolver resolver(ioc);
        tcp::resolver::results_type endpoints;
        auto ec = run([&](auto handler) {
            resolver.async_resolve(server.host, server.port,
                [&endpoints, handler](beast::error_code e, tcp::resolver::results_type r) mutable {
                    endpoints = std::move(r);
                    handler(e);
                });
        });
        if (ec) network_error("cannot resolve", ec);
        stream.expires_after(timeout);
        ec = run([&](auto handler) { stream.async_connect(endpoints, handler); });
        if (ec) network_error("cannot connect to", ec);
        connected = true;
    }

    http::request<http::string_body> make_request(http::verb verb, std::string_view target, std::string body,
        const std::vector<std::pair<std::string, std::string>>& headers)
    {
        http::request<http::string_body> req{verb, server.base_path + std::string(target), 11};
        req.set(http::field::host, server.host + ":" + server.port);
        req.set(http::field::user_agent, user_agent);
        if (!token.empty()) req.set(http::field::authorization, "Bearer " + token);
        for (const auto& [k, v] : headers) req.set(k, v);
        if (!body.empty() && req.find(http::field::content_type) == req.end())
            req.set(http::field::content_type, "application/json");
        req.body() = std::move(body);
        req.keep_alive(true);
        req.prepare_payload();
        return req;
    }

    /// Writes the request; false if a reused connection was found closed.
    bool send(const http::request<http::string_body>& req, bool reused)
    {
        stream.expires_after(timeout);
        const auto ec = run([&](auto handler) { http::async_write(stream, req, handler); });
        if (!ec) return true;
        if (reused && is_connection_closed(ec)) {
            close();
            return false;
        }
        network_error("cannot send to", ec);
    }
};

HttpClient::HttpClient(ServerUrl server, std::string token, std::chrono::milliseconds timeout)
    : server_(server), impl_(std::make_unique<Impl>())
{
    impl_->server = std::move(server);
    impl_->token = std::move(token);
    impl_->timeout = timeout;
}

HttpClient::~HttpClient() = default;

HttpReply HttpClient::request(Method method, std::string_view target, std::string body,
    const std::vector<std::pair<std::string, std::string>>& headers)
{
    Impl& m = *impl_;
    const auto req = m.make_request(to_verb(method), target, std::move(body), headers);
    for (int attempt = 0;; ++attempt) {
        const bool reused = m.connected;
        if (!m.connected) m.connect();
        if (!m.send(req, reused && attempt == 0)) continue;
        http::response_parser<http::string_body> parser;
        parser.body_limit(max_reply_bytes);
        if (method == Method::head) parser.skip(true);
        m.stream.expires_after(m.timeout);
        const auto ec = m.run([&](auto handler) { http::async_read(m.stream, m.buffer, parser, handler); });
        if (ec) {
            // A keep-alive connection the server closed meanwhile: once more on a new one.
            if (reused && attempt == 0 && is_connection_closed(ec) && !parser.got_some()) {
                m.close();
                continue;
            }
            m.network_error("no reply from", ec);
        }
        HttpReply reply;
        reply.status = parser.get().result_int();
        reply.headers = header_map(parser.get());
        reply.body = std::move(parser.get().body());
        if (!parser.keep_alive()) m.close();
        return reply;
    }
}

HttpReply HttpClient::download(std::string_view target, const std::filesystem::path& file, std::uint64_t offset,
    const std::string& if_range, const std::function<void(std::uint64_t)>& on_bytes)
{
    Impl& m = *impl_;
    std::vector<std::pair<std::string, std::string>> headers;
    if (offset > 0) {
        headers.emplace_back("Range", "bytes=" + std::to_string(offset) + "-");
        headers.emplace_back("If-Range", if_range);
    }
    const auto req = m.make_request(http::verb::get, target, {}, headers);
    for (int attempt = 0;; ++attempt) {
        const bool reused = m.connected;
        if (!m.connected) m.connect();
        if (!m.send(req, reused && attempt == 0)) continue;

        http::response_parser<http::buffer_body> parser;
        parser.body_limit(boost::none);
        m.stream.expires_after(m.timeout);
        auto ec = m.run([&](auto handler) { http::async_read_header(m.stream, m.buffer, parser, handler); });
        if (ec) {
            if (reused && attempt == 0 && is_connection_closed(ec) && !parser.got_some()) {
                m.close();
                continue;
            }
            m.network_error("no reply from", ec);
        }
        HttpReply reply;
        reply.status = parser.get().result_int();
        reply.headers = header_map(parser.get());
        const bool to_file = reply.status == 200 || (reply.status == 206 && offset > 0);
        if (reply.status == 206 && reply.header("content-range").rfind("bytes " + std::to_string(offset) + "-", 0) != 0) {
            m.close();
            throw CommandError(exit_code::server_refused,
                "server sent the wrong range (" + reply.header("content-range") + "); asked from byte " + std::to_string(offset));
        }
        int fd = -1;
        std::uint64_t size = 0;
        if (to_file) {
            const int flags = O_WRONLY | O_CREAT | O_CLOEXEC | (reply.status == 206 ? O_APPEND : O_TRUNC);
            fd = ::open(file.c_str(), flags, 0644);
            if (fd < 0) {
                m.close();
                throw CommandError(exit_code::local_io, "cannot write " + file.string() + ": " + std::strerror(errno));
            }
            size = reply.status == 206 ? offset : 0;
        }
        std::array<char, 64 * 1024> chunk{};
        while (!parser.is_done()) {
            parser.get().body().data = chunk.data();
            parser.get().body().size = chunk.size();
            m.stream.expires_after(m.timeout);
            ec = m.run([&](auto handler) { http::async_read(m.stream, m.buffer, parser, handler); });
            if (ec == http::error::need_buffer) ec = {};
            const std::size_t got = chunk.size() - parser.get().body().size;
            if (to_file) {
                for (std::size_t done = 0; done < got;) {
                    const ssize_t w = ::write(fd, chunk.data() + done, got - done);
                    if (w < 0 && errno == EINTR) continue;
                    if (w <= 0) {
                        const std::string why = std::strerror(errno);
                        ::close(fd);
                        m.close();
                        throw CommandError(exit_code::local_io, "cannot write " + file.string() + ": " + why);
                    }
                    done += static_cast<std::size_t>(w);
                }
                size += got;
                on_bytes(size);
            } else if (reply.body.size() < max_reply_bytes) {
                reply.body.append(chunk.data(), got);
            }
            if (ec) {
                if (fd >= 0) ::close(fd);
                m.network_error("download interrupted from", ec);
            }
        }
        if (fd >= 0 && ::close(fd) != 0)
            throw CommandError(exit_code::local_io, "cannot write " + file.string() + ": " + std::strerror(errno));
        if (!parser.keep_alive()) m.close();
        return reply;
    }
}

} // namespace wiredem::client
