// A Beast body that streams one byte range of an open file with pread, so a
// download of a large result.h5 never sits in memory and can resume (Range).
// Beast's own file_body always sends the whole file.
#pragma once

#include <boost/asio/buffer.hpp>
#include <boost/beast/core/error.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/optional.hpp>

#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <memory>
#include <utility>

namespace wiredem::server {

/// Body type for http::response<FileRangeBody>.
struct FileRangeBody {
    /// An open file (shared, closed with the last copy) and the range to send.
    struct value_type {
        std::shared_ptr<int> fd;        ///< owning descriptor; null: nothing to send
        std::uint64_t offset = 0;       ///< first byte sent
        std::uint64_t length = 0;       ///< bytes sent from offset
    };

    /// Content-Length of the body.
    static std::uint64_t size(const value_type& v) { return v.length; }

    /// Reads the file in chunks into a buffer owned by the writer.
    class writer {
    public:
        using const_buffers_type = boost::asio::const_buffer;

        template <bool IsRequest, class Fields>
        writer(const boost::beast::http::header<IsRequest, Fields>&, const value_type& body) : body_(body)
        {
        }

        void init(boost::beast::error_code& ec) { ec = {}; }

        boost::optional<std::pair<const_buffers_type, bool>> get(boost::beast::error_code& ec)
        {
            const std::uint64_t remain = body_.length - sent_;
            if (remain == 0 || !body_.fd) {
                ec = {};
                return boost::none;
            }
            const std::size_t want = remain < buf_.size() ? static_cast<std::size_t>(remain) : buf_.size();
            ssize_t got;
            do {
                got = ::pread(*body_.fd, buf_.data(), want, static_cast<off_t>(body_.offset + sent_));
            } while (got < 0 && errno == EINTR);
            if (got < 0) {
                ec = boost::beast::error_code(errno, boost::system::generic_category());
                return boost::none;
            }
            if (got == 0) {  // the file shrank under us: the response cannot be completed
                ec = boost::beast::error_code(EIO, boost::system::generic_category());
                return boost::none;
            }
            sent_ += static_cast<std::uint64_t>(got);
            ec = {};
            return {{const_buffers_type(buf_.data(), static_cast<std::size_t>(got)), sent_ < body_.length}};
        }

    private:
        const value_type& body_;
        std::uint64_t sent_ = 0;
        std::array<char, 64 * 1024> buf_{};
    };
};

} // namespace wiredem::server
