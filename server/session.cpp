// The per-connection state machine: wait → read → dispatch → write → wait …,
// with a deadline on every read and on every chunk written (slow clients are
// cut off), and a lingering close after an error reply so the client reads
// the reply instead of a reset.
//
// Idle connections (nothing of a request received yet: just accepted, or
// kept alive between requests) get the short --idle-timeout, and they and
// the connections whose request's headers are still coming are the ones
// given up when --max-connections are open and another client connects: a
// client holding many connections idle, or each with a byte sent, cannot
// lock the others out. Only when every connection is busy with a request
// whose headers are in is a newcomer refused, with a 503.
#include "session.hpp"

#include "framing.hpp"

#include <boost/asio/dispatch.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/core/bind_handler.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/error.hpp>
#include <boost/beast/http/parser.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/serializer.hpp>
#include <boost/beast/http/write.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <list>
#include <mutex>
#include <optional>

namespace wiredem::server {
namespace asio = boost::asio;
namespace beast = boost::beast;
using tcp = asio::ip::tcp;

class Session;

/// The open connections: their number, and the idle ones oldest first.
/// Thread-safe (a mutex; each call is a few list operations).
class ConnectionTable {
public:
    /// Counts a new connection in if there is room, making room by closing
    /// the longest idle one when needed; false when every one is busy.
    bool admit(std::size_t max_connections);
    /// A session ended.
    void leave();
    /// A session waits for a request: it may be closed to make room.
    std::list<std::weak_ptr<Session>>::iterator idle(std::weak_ptr<Session> s);
    /// It received the start of a request (or ended): it is kept.
    void busy(std::list<std::weak_ptr<Session>>::iterator it);

private:
    std::mutex mutex_;
    std::size_t open_ = 0;
    std::list<std::weak_ptr<Session>> idle_;
};

class Session : public std::enable_shared_from_this<Session> {
public:
    /// `table`: the table that counted this connection in, or null for one
    /// to be refused (refuse()).
    Session(tcp::socket&& socket, Router& router, const ServerConfig& config, Metrics& metrics,
        std::shared_ptr<ConnectionTable> table)
        : stream_(std::move(socket)), buffer_(read_buffer_limit(config.max_header_bytes)), router_(router), config_(config), metrics_(metrics), table_(std::move(table))
    {
        beast::error_code ec;
        const auto ep = stream_.socket().remote_endpoint(ec);
        peer_ = ec ? std::string("?") : ep.address().to_string() + ":" + std::to_string(ep.port());
        metrics_.connections_open.fetch_add(1, std::memory_order_relaxed);
    }
    ~Session()
    {
        metrics_.connections_open.fetch_sub(1, std::memory_order_relaxed);
        if (table_) table_->leave();
    }

    void run() { asio::dispatch(stream_.get_executor(), beast::bind_front_handler(&Session::do_read, shared_from_this())); }

    /// Every connection is busy with a request: this one hears so (503,
    /// Retry-After) rather than being dropped, and is closed.
    void refuse()
    {
        asio::dispatch(stream_.get_executor(), [self = shared_from_this()] {
            self->reply_and_close(http::status::service_unavailable, "too_many_connections",
                "all " + std::to_string(self->config_.max_connections)
                    + " connections are busy with requests; retry shortly",
                "1");
        });
    }

    /// Claims this idle session to be closed for room; false when another
    /// newcomer claimed it already. Any thread.
    bool claim_for_eviction() { return !evicting_.exchange(true); }

    /// Closes an idle connection to make room for another (called from any
    /// thread once claimed; the close runs on this session's strand).
    void evict()
    {
        asio::post(stream_.get_executor(), [self = shared_from_this()] {
            if (!self->idle_entry_) return;  // its request began meanwhile: kept
            self->evicted_ = true;
            beast::error_code ec;
            self->stream_.socket().close(ec);  // the pending wait ends with operation_aborted
        });
    }

private:
    /// Waits for the next request: bytes already buffered (pipelining) are
    /// one; otherwise the connection is idle until its first byte arrives.
    void do_read()
    {
        if (buffer_.size() > 0) return read_request();
        evicting_ = false;  // a claim that came as its last request began has lapsed
        idle_entry_ = table_->idle(weak_from_this());
        stream_.expires_after(config_.idle_timeout);
        stream_.async_read_some(buffer_.prepare(std::min(first_read_bytes, buffer_.max_size())), [self = shared_from_this()](beast::error_code ec, std::size_t n) {
            if (ec) self->leave_idle();
            if (ec == asio::error::eof) return self->do_close();
            if (ec) return self->log_failure(ec, self->evicted_ ? "idle, closed to make room" : "idle");
            self->buffer_.commit(n);
            self->read_request();  // still evictable until its headers are in (on_header)
        });
    }

    /// The session leaves the idle list: from here on it is not closed to
    /// make room. That is once a request's headers are complete, not at its
    /// first byte: connections that each sent a byte held every place for the
    /// read timeout, and newcomers heard 503 until then.
    void leave_idle()
    {
        if (!idle_entry_) return;
        table_->busy(*idle_entry_);
        idle_entry_.reset();
    }

    void read_request()
    {
        parser_.emplace();
        parser_->body_limit(config_.max_body_bytes);
        parser_->header_limit(config_.max_header_bytes);
        stream_.expires_after(config_.read_timeout);
        http::async_read_header(stream_, buffer_, *parser_, beast::bind_front_handler(&Session::on_header, shared_from_this()));
    }

    /// The headers are in: a request whose body framing cannot be trusted
    /// (server/framing.hpp) is refused before its body is read, and the
    /// connection closed.
    void on_header(beast::error_code ec, std::size_t bytes)
    {
        leave_idle();
        if (ec) return on_read(ec, bytes);
        if (auto problem = framing_problem(parser_->get()))
            return reply_and_close(problem->status, problem->code, problem->message);
        if (expects_continue(parser_->get())) {  // the client sends its body once it has this
            auto interim = std::make_shared<http::response<http::empty_body>>(http::status::continue_, 11);
            return http::async_write(stream_, *interim, [self = shared_from_this(), interim](beast::error_code wec, std::size_t) {
                if (wec) return self->log_failure(wec, "write");
                self->read_body();
            });
        }
        read_body();
    }

    void read_body()
    {
        http::async_read(stream_, buffer_, *parser_, beast::bind_front_handler(&Session::on_read, shared_from_this()));
    }

    void on_read(beast::error_code ec, std::size_t)
    {
        if (ec == http::error::end_of_stream) return do_close();
        // tcp_stream closes the socket when its deadline passes, so a stalled
        // client gets no 408, just the closed connection.
        if (ec == beast::error::timeout) return log_failure(ec, "read");
        if (ec == http::error::body_limit)
            return reply_and_close(http::status::payload_too_large, "body_too_large",
                "request body exceeds " + std::to_string(config_.max_body_bytes) + " bytes");
        if (ec == http::error::header_limit)
            return reply_and_close(http::status::request_header_fields_too_large, "headers_too_large",
                "request headers exceed " + std::to_string(config_.max_header_bytes) + " bytes");
        if (ec == http::error::buffer_overflow)  // a chunked body's trailer or chunk line: read_buffer_limit
            return reply_and_close(http::status::request_header_fields_too_large, "headers_too_large",
                "a chunked body's trailer or chunk line exceeds " + std::to_string(config_.max_header_bytes) + " bytes");
        if (ec && ec.category() == http::make_error_code(http::error::bad_target).category())  // ill-formed HTTP
            return reply_and_close(http::status::bad_request, "bad_request", "malformed HTTP request: " + ec.message());
        if (ec) return log_failure(ec, "read");

        const auto t0 = std::chrono::steady_clock::now();
        if (Router::lane_of(parser_->get()) != Router::Lane::io) {
            // Answered on a submit or data thread; the reply comes back to
            // this session's strand. No read is pending meanwhile.
            auto req = std::make_shared<const Request>(parser_->release());
            router_.dispatch_later(req, [self = shared_from_this(), req, t0](std::shared_ptr<Response> res) {
                asio::post(self->stream_.get_executor(), [self, req, t0, res = std::move(res)] {
                    self->log_access(*req, status_of(*res), std::chrono::steady_clock::now() - t0);
                    self->send(std::move(*res));
                });
            });
            return;
        }
        Request req = parser_->release();
        Response res = router_.dispatch(req);
        log_access(req, status_of(res), std::chrono::steady_clock::now() - t0);
        send(std::move(res));
    }

    void send(Response&& res)
    {
        std::visit([this](auto& r) { write_message(std::make_shared<std::decay_t<decltype(r)>>(std::move(r))); }, res);
    }

    /// Writes the message chunk by chunk; each chunk gets write_timeout, so a
    /// large download may take long but a stalled client cannot hold the session.
    template <class Body>
    void write_message(std::shared_ptr<http::response<Body>> msg)
    {
        close_after_write_ = msg->need_eof();
        auto sr = std::make_shared<http::response_serializer<Body>>(*msg);
        write_some(std::move(msg), std::move(sr));
    }

    template <class Body>
    void write_some(std::shared_ptr<http::response<Body>> msg, std::shared_ptr<http::response_serializer<Body>> sr)
    {
        stream_.expires_after(config_.write_timeout);
        auto& serializer = *sr;
        http::async_write_some(stream_, serializer,
            [self = shared_from_this(), msg = std::move(msg), sr = std::move(sr)](beast::error_code ec, std::size_t) mutable {
                if (ec) return self->log_failure(ec, "write");
                if (!sr->is_done()) return self->write_some(std::move(msg), std::move(sr));
                if (self->close_after_write_) return self->do_close();
                self->do_read();
            });
    }

    void reply_and_close(http::status status, std::string_view code, const std::string& message,
        std::string_view retry_after = {})
    {
        Request stub;
        stub.version(11);
        stub.keep_alive(false);
        auto res = error_response(stub, status, code, message);
        if (!retry_after.empty()) res.set(http::field::retry_after, retry_after);
        const unsigned cls = res.result_int() / 100;
        metrics_.responses_by_class[cls].fetch_add(1, std::memory_order_relaxed);
        spdlog::info("{} - {} {}", peer_, res.result_int(), message);
        send(Response(std::move(res)));
    }

    /// Half-close, then read and discard what the client still sends (at
    /// most linger_time), so an early error reply is not lost to a reset.
    void do_close()
    {
        beast::error_code ec;
        stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
        if (ec) return;
        stream_.expires_after(std::chrono::seconds(2));
        drain();
    }

    void drain()
    {
        stream_.async_read_some(asio::buffer(discard_), [self = shared_from_this()](beast::error_code ec, std::size_t) {
            if (!ec) self->drain();
        });
    }

    void log_failure(beast::error_code ec, const char* what)
    {
        if (ec == asio::error::operation_aborted || ec == beast::error::timeout || ec == asio::error::eof
            || ec == asio::error::connection_reset || ec == asio::error::broken_pipe)
            spdlog::debug("{} - {}: {}", peer_, what, ec.message());
        else
            spdlog::warn("{} - {}: {}", peer_, what, ec.message());
    }

    void log_access(const Request& req, unsigned status, std::chrono::steady_clock::duration took)
    {
        const double ms = std::chrono::duration<double, std::milli>(took).count();
        const bool quiet = (req.method() == http::verb::get || req.method() == http::verb::head) && status < 400;
        spdlog::log(quiet ? spdlog::level::debug : spdlog::level::info, "{} - {} {} {} {:.2f} ms", peer_,
            std::string(req.method_string()), std::string(req.target()), status, ms);
    }

    beast::tcp_stream stream_;
    beast::flat_buffer buffer_;  ///< at most read_buffer_limit bytes
    std::optional<http::request_parser<http::string_body>> parser_;
    Router& router_;
    const ServerConfig& config_;
    Metrics& metrics_;
    /// The first read of a request takes what has arrived, up to this.
    static constexpr std::size_t first_read_bytes = 4096;

    std::string peer_;
    bool close_after_write_ = false;
    std::shared_ptr<ConnectionTable> table_;  ///< shared: a session may outlive its listener
    /// Set while the session is idle: its place in the table's idle list.
    std::optional<std::list<std::weak_ptr<Session>>::iterator> idle_entry_;
    bool evicted_ = false;
    std::atomic<bool> evicting_{false};
    std::array<char, 4096> discard_{};
};

bool ConnectionTable::admit(std::size_t max_connections)
{
    std::shared_ptr<Session> victim;
    {
        std::lock_guard lock(mutex_);
        if (open_ >= max_connections) {
            // The longest idle session still alive goes (its entry leaves the
            // list when its wait ends, as every idle entry does).
            for (auto it = idle_.begin(); it != idle_.end() && !victim; ++it)
                if (auto s = it->lock(); s && s->claim_for_eviction()) victim = std::move(s);
            if (!victim) return false;
        }
        ++open_;
    }
    if (victim) victim->evict();
    return true;
}

void ConnectionTable::leave()
{
    std::lock_guard lock(mutex_);
    --open_;
}

std::list<std::weak_ptr<Session>>::iterator ConnectionTable::idle(std::weak_ptr<Session> s)
{
    std::lock_guard lock(mutex_);
    return idle_.insert(idle_.end(), std::move(s));
}

void ConnectionTable::busy(std::list<std::weak_ptr<Session>>::iterator it)
{
    std::lock_guard lock(mutex_);
    idle_.erase(it);
}

std::shared_ptr<ConnectionTable> make_connection_table() { return std::make_shared<ConnectionTable>(); }

void start_session(tcp::socket socket, Router& router, const ServerConfig& config, Metrics& metrics,
    std::shared_ptr<ConnectionTable> table)
{
    if (!table->admit(config.max_connections)) {
        metrics.connections_rejected.fetch_add(1, std::memory_order_relaxed);
        std::make_shared<Session>(std::move(socket), router, config, metrics, nullptr)->refuse();
        return;
    }
    std::make_shared<Session>(std::move(socket), router, config, metrics, std::move(table))->run();
}

} // namespace wiredem::server
