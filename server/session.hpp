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

/// The open connections of a listener (session.cpp): counted against
/// --max-connections, the idle ones closed first to make room.
class ConnectionTable;
[[nodiscard]] std::shared_ptr<ConnectionTable> make_connection_table();

/// Starts serving a connection that was just accepted (the socket's executor
/// must be a strand). The session keeps itself alive until the connection
/// ends. With --max-connections open, the longest idle one is closed to let
/// this one in; when none is idle, this one gets a 503 and is closed.
void start_session(boost::asio::ip::tcp::socket socket, Router& router, const ServerConfig& config,
    Metrics& metrics, std::shared_ptr<ConnectionTable> connections);

} // namespace wiredem::server
