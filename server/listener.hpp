// Accepts connections and gives each its own strand and Session. Survives
// accept errors (e.g. out of descriptors) by pausing briefly.
// Thread safety: run() and stop() may be called from any thread.
#pragma once

#include "config.hpp"
#include "router.hpp"
#include "session.hpp"

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>

#include <memory>

namespace wiredem::server {

/// The accept loop of one listening address.
class Listener : public std::enable_shared_from_this<Listener> {
public:
    /// Opens, binds and listens. @throws boost::system::system_error when the
    /// address cannot be bound.
    Listener(boost::asio::io_context& ioc, const boost::asio::ip::tcp::endpoint& endpoint, Router& router,
        const ServerConfig& config, Metrics& metrics);

    /// The bound address (the real port when 0 was asked for).
    [[nodiscard]] boost::asio::ip::tcp::endpoint local_endpoint() const;

    /// Starts accepting.
    void run();

    /// Stops accepting; open connections carry on.
    void stop();

private:
    void do_accept();
    void on_accept(boost::system::error_code ec, boost::asio::ip::tcp::socket socket);

    boost::asio::io_context& ioc_;
    boost::asio::ip::tcp::acceptor acceptor_;
    boost::asio::steady_timer backoff_;
    Router& router_;
    const ServerConfig& config_;
    Metrics& metrics_;
    std::shared_ptr<ConnectionTable> connections_ = make_connection_table();
};

/// Runs `ioc` on the calling thread until it is stopped. No exception ends an
/// I/O thread, and with it the server: one that escapes a handler is logged and
/// the loop resumes (asio allows run() again after a throw). The handler that
/// threw is destroyed in the unwinding, and with it its hold on a session, so
/// that connection is closed; every other one carries on. The causes known
/// are prevented where they arise (Beast's std::length_error for a field of
/// 64 KiB: read_buffer_limit); this is the net for the unknown ones.
void run_io_loop(boost::asio::io_context& ioc) noexcept;

} // namespace wiredem::server
