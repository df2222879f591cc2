// One client connection: read a request (with header, body and time limits),
// hand it to the router, write the reply, repeat while keep-alive holds.
// All of a session's handlers run on its own strand, so a session needs no
// locks; the router and services it calls are thread-safe.
#pragma once

#include "config.hpp"
#include "router.hpp"

#include <boost/asio/ip/tcp.hpp>

#include <memory>

namespace wiredem::server {

/// Starts serving a connection that was just accepted (the socket's executor
/// must be a strand). The session keeps itself alive until the connection ends.
void start_session(boost::asio::ip::tcp::socket socket, Router& router, const ServerConfig& config,
    Metrics& metrics);

} // namespace wiredem::server
