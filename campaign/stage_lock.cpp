#include "stage_lock.hpp"

#include "core/format.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

namespace wiredem::campaign {
namespace {

/// What the holder wrote into the lock file ("pid 1234 on host"), or "".
std::string holder_of(int fd)
{
    std::array<char, 256> buffer{};
    const ssize_t n = ::pread(fd, buffer.data(), buffer.size() - 1, 0);
    if (n <= 0) return {};
    std::string text(buffer.data(), static_cast<std::size_t>(n));
    while (!text.empty() && (text.back() == '\n' || text.back() == '\0')) text.pop_back();
    return text;
}

} // namespace

engine::Result<StageLock, std::string> StageLock::acquire(
    const std::filesystem::path& file, const std::string& what, double wait_s, const std::atomic<bool>* cancel)
{
    const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) return engine::Err("cannot open the lock file " + file.string() + ": " + std::strerror(errno));
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(std::max(0.0, wait_s));
    int locked = ::flock(fd, LOCK_EX | LOCK_NB);
    while (locked != 0 && errno == EWOULDBLOCK && std::chrono::steady_clock::now() < until
           && !(cancel && cancel->load())) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        locked = ::flock(fd, LOCK_EX | LOCK_NB);
    }
    if (locked != 0) {
        const int error = errno;
        if (error == ENOLCK || error == ENOSYS || error == EOPNOTSUPP) { // no locks here: run unguarded
            ::close(fd);
            return StageLock(-1);
        }
        std::string message;
        if (error == EWOULDBLOCK) {
            const std::string holder = holder_of(fd);
            const std::string waited = engine::format_number(std::max(0.0, wait_s), 6) + " s";
            message = what + " is already running in another process" + (holder.empty() ? "" : " (" + holder + ")")
                    + ", which holds " + file.string() + " (waited " + waited + "); wait for it to end or stop it";
        } else {
            message = "cannot lock " + file.string() + ": " + std::strerror(error);
        }
        ::close(fd);
        return engine::Err(message);
    }
    // Who holds it, for the message another process gets.
    std::array<char, 128> host{};
    if (::gethostname(host.data(), host.size() - 1) != 0) host[0] = '\0';
    const std::string holder = "pid " + std::to_string(::getpid()) + " on " + (host[0] ? host.data() : "this host") + "\n";
    if (::ftruncate(fd, 0) == 0) {
        [[maybe_unused]] const ssize_t written = ::pwrite(fd, holder.data(), holder.size(), 0);
    }
    return StageLock(fd);
}

StageLock& StageLock::operator=(StageLock&& other) noexcept
{
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = other.fd_;
        other.fd_ = -1;
    }
    return *this;
}

StageLock::~StageLock()
{
    if (fd_ >= 0) ::close(fd_); // closing the last descriptor drops the lock
}

} // namespace wiredem::campaign
