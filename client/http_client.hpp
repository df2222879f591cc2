// A small blocking HTTP/1.1 client for the wiredem API (Boost.Beast): one
// keep-alive connection, a deadline on every operation, one transparent
// reconnect when a reused connection turns out closed, and streaming
// downloads straight to a file (so result.h5 never sits in memory).
//
// Network problems throw CommandError(exit_code::network, "<one line>").
// Not thread-safe: one client per thread.
#pragma once

#include "exit_codes.hpp"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wiredem::client {

/// Where the server is: from --server / WIREDEM_SERVER, parsed with Boost.URL.
struct ServerUrl {
    std::string host;       ///< name or address (IPv6 without brackets)
    std::string port;       ///< "80" when the URL gives none
    std::string base_path;  ///< path prefix before /v1 (a reverse proxy's mount point), no trailing '/'
    std::string text;       ///< the URL as given, for messages
};

/// Parses `http://host[:port][/prefix]`. @throws CommandError(usage) for
/// anything else (https included: put a TLS proxy in front and use its URL from there).
[[nodiscard]] ServerUrl parse_server_url(std::string_view url);

/// A reply whose body was read into memory.
struct HttpReply {
    unsigned status = 0;
    std::map<std::string, std::string> headers;  ///< lower-case names
    std::string body;
    /// Header value or "" (name in lower case).
    [[nodiscard]] std::string header(const std::string& name) const;
};

/// The HTTP methods the API uses.
enum class Method { get, head, post, del };

/// One connection's worth of API calls (see the file comment).
class HttpClient {
public:
    /// @param token     bearer token ("" to send none)
    /// @param timeout   limit for connecting and for each read or write
    HttpClient(ServerUrl server, std::string token, std::chrono::milliseconds timeout);
    ~HttpClient();
    HttpClient(const HttpClient&) = delete;
    HttpClient& operator=(const HttpClient&) = delete;

    /// Sends one request to base_path + `target` and reads the whole reply
    /// (at most 64 MiB).
    HttpReply request(Method method, std::string_view target, std::string body = {},
        const std::vector<std::pair<std::string, std::string>>& headers = {});

    /// GETs `target` into `file`. With `offset` > 0 asks for the bytes from
    /// there on (Range, only if the representation is still `if_range`, an
    /// ETag) and appends when the server answers 206; a 200 (also what a
    /// changed representation gets) rewrites the file from the start. Bytes
    /// are written as they arrive, so an interrupted download keeps what it
    /// got. A reply other than 200/206 is returned with its body and the file
    /// untouched.
    /// @param on_bytes called with the file's size after each chunk
    HttpReply download(std::string_view target, const std::filesystem::path& file, std::uint64_t offset,
        const std::string& if_range, const std::function<void(std::uint64_t)>& on_bytes);

    /// The server this client talks to.
    [[nodiscard]] const ServerUrl& server() const { return server_; }

private:
    struct Impl;
    ServerUrl server_;
    std::unique_ptr<Impl> impl_;
};

} // namespace wiredem::client
