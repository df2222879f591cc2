// The accept loop; all of it runs on the acceptor's strand.
#include "listener.hpp"

#include "session.hpp"

#include <boost/asio/post.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core/bind_handler.hpp>
#include <spdlog/spdlog.h>

namespace wiredem::server {
namespace asio = boost::asio;
using tcp = asio::ip::tcp;

Listener::Listener(asio::io_context& ioc, const tcp::endpoint& endpoint, Router& router, const ServerConfig& config,
    Metrics& metrics)
    : ioc_(ioc), acceptor_(asio::make_strand(ioc)), backoff_(acceptor_.get_executor()), router_(router),
      config_(config), metrics_(metrics)
{
    acceptor_.open(endpoint.protocol());
    acceptor_.set_option(asio::socket_base::reuse_address(true));
    acceptor_.bind(endpoint);
    acceptor_.listen(asio::socket_base::max_listen_connections);
}

tcp::endpoint Listener::local_endpoint() const { return acceptor_.local_endpoint(); }

void Listener::run()
{
    asio::post(acceptor_.get_executor(), [self = shared_from_this()] { self->do_accept(); });
}

void Listener::stop()
{
    asio::post(acceptor_.get_executor(), [self = shared_from_this()] {
        boost::system::error_code ec;
        self->acceptor_.close(ec);
        self->backoff_.cancel();
    });
}

void Listener::do_accept()
{
    acceptor_.async_accept(asio::make_strand(ioc_), boost::beast::bind_front_handler(&Listener::on_accept, shared_from_this()));
}

void Listener::on_accept(boost::system::error_code ec, tcp::socket socket)
{
    if (!acceptor_.is_open()) return;
    if (ec) {
        spdlog::warn("accept: {}", ec.message());
        // e.g. out of file descriptors: pause instead of spinning
        backoff_.expires_after(std::chrono::milliseconds(100));
        backoff_.async_wait([self = shared_from_this()](boost::system::error_code wait_ec) {
            if (!wait_ec && self->acceptor_.is_open()) self->do_accept();
        });
        return;
    }
    socket.set_option(tcp::no_delay(true), ec);
    start_session(std::move(socket), router_, config_, metrics_, connections_);
    do_accept();
}

void run_io_loop(asio::io_context& ioc) noexcept
{
    for (;;) {
        try {
            ioc.run();
            return;
        } catch (const std::exception& e) {
            spdlog::error("an I/O handler threw ({}): its connection is closed, the server carries on", e.what());
        } catch (...) {
            spdlog::error("an I/O handler threw: its connection is closed, the server carries on");
        }
    }
}

} // namespace wiredem::server
