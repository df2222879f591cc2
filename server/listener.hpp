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

} // namespace wiredem::server
