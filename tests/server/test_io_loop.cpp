// run_io_loop: an exception that escapes an I/O handler ends neither the
// thread nor the loop (server/listener.hpp).
#include "listener.hpp"

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

namespace wiredem::server {
namespace {

TEST(IoLoop, AnExceptionFromAHandlerDoesNotEndTheLoop)
{
    boost::asio::io_context ioc;
    int ran = 0;
    // What the handler held (a session, in the server) is released as the
    // exception unwinds it.
    auto held = std::make_shared<int>(1);
    std::weak_ptr<int> watch = held;
    boost::asio::post(ioc, [held = std::move(held)] { throw std::length_error("field value too large"); });
    boost::asio::post(ioc, [&] { ++ran; });
    boost::asio::post(ioc, [] { throw 42; });  // not even a std::exception
    boost::asio::post(ioc, [&] { ++ran; });
    run_io_loop(ioc);  // returns once the queue is empty, as ioc.run() does
    EXPECT_EQ(ran, 2);
    EXPECT_TRUE(watch.expired());
}

} // namespace
} // namespace wiredem::server
