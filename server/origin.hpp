// Who may talk to the server from a browser: the Host a request names and the
// Origin it comes from (DNS rebinding and cross-site requests). A page on
// another site can make a browser send requests to a loopback server; the
// Host check refuses them when the attacker's name points at 127.0.0.1, and the
// Origin check when the page simply posts across sites. Pure functions of the
// request's header values and the configuration; no I/O.
#pragma once

#include "config.hpp"

#include <optional>
#include <string>
#include <string_view>

namespace wiredem::server {

/// Why a Host header is refused, or nullopt when it is one of the server's own
/// names: the listen address, `localhost` when listening on loopback, and every
/// --allowed-host; with the listen port, or without a port. Listening on a
/// wildcard address (0.0.0.0, ::) with no --allowed-host accepts any name.
[[nodiscard]] std::optional<std::string> host_problem(std::string_view host, const ServerConfig& config);

/// Why an Origin header is refused, or nullopt when it is the server's own
/// origin as the request addressed it: `http://` + the (already accepted) Host.
/// "null" (sandboxed pages, file: URLs) is refused.
[[nodiscard]] std::optional<std::string> origin_problem(std::string_view origin, std::string_view host);

} // namespace wiredem::server
