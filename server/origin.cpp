#include "origin.hpp"

#include <boost/asio/ip/address.hpp>
#include <boost/beast/core/string.hpp>

#include <algorithm>
#include <charconv>

namespace wiredem::server {
namespace {

/// "name", "name:port", "[v6]" or "[v6]:port" → name (brackets removed) and port text.
bool split_host(std::string_view host, std::string_view& name, std::string_view& port)
{
    if (host.empty()) return false;
    if (host.front() == '[') {
        const auto close = host.find(']');
        if (close == std::string_view::npos) return false;
        name = host.substr(1, close - 1);
        const std::string_view rest = host.substr(close + 1);
        if (rest.empty()) return true;
        if (rest.front() != ':') return false;
        port = rest.substr(1);
        return true;
    }
    const auto colon = host.rfind(':');
    name = host.substr(0, colon);
    if (colon != std::string_view::npos) port = host.substr(colon + 1);
    return !name.empty() && name.find(':') == std::string_view::npos;
}

bool is_wildcard(const std::string& address)
{
    boost::system::error_code ec;
    const auto a = boost::asio::ip::make_address(address, ec);
    return !ec && a.is_unspecified();
}

bool is_loopback(const std::string& address)
{
    boost::system::error_code ec;
    const auto a = boost::asio::ip::make_address(address, ec);
    return !ec && a.is_loopback();
}

} // namespace

std::optional<std::string> host_problem(std::string_view host, const ServerConfig& config)
{
    std::string_view name, port;
    if (!split_host(host, name, port)) return "the Host header '" + std::string(host) + "' is not HOST[:PORT]";
    if (!port.empty()) {
        unsigned value = 0;
        const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
        if (ec != std::errc() || end != port.data() + port.size() || value != config.listen_port)
            return "the Host header names port " + std::string(port) + "; this server listens on "
                 + std::to_string(config.listen_port);
    }
    const auto same = [&](std::string_view allowed) { return boost::beast::iequals(name, allowed); };
    if (same(config.listen_host)) return std::nullopt;
    if (is_loopback(config.listen_host) && same("localhost")) return std::nullopt;
    if (std::any_of(config.allowed_hosts.begin(), config.allowed_hosts.end(), same)) return std::nullopt;
    if (is_wildcard(config.listen_host) && config.allowed_hosts.empty()) return std::nullopt;
    return "the Host header names '" + std::string(name) + "', which is not this server (" + config.listen_host
         + (is_loopback(config.listen_host) ? ", localhost" : "") + " or an --allowed-host)";
}

std::optional<std::string> origin_problem(std::string_view origin, std::string_view host)
{
    constexpr std::string_view scheme = "http://";
    if (origin.size() > scheme.size() && boost::beast::iequals(origin.substr(0, scheme.size()), scheme)
        && boost::beast::iequals(origin.substr(scheme.size()), host))
        return std::nullopt;
    return "requests from the origin '" + std::string(origin) + "' are refused: only pages served by this server (http://"
         + std::string(host) + ") may call it";
}

} // namespace wiredem::server
