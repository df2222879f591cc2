#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <string>
#include <system_error>

namespace wiredem::engine::io {
namespace {

/// "No space left on device" → "no space left on device writing FILE".
std::string write_error_text(int error_number, const std::filesystem::path& file)
{
    std::string reason = std::generic_category().message(error_number);
    if (!reason.empty()) reason[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(reason[0])));
    return reason + " writing " + file.string();
}

} // namespace

WriteError::WriteError(int error_number, const std::filesystem::path& file)
    : std::runtime_error(write_error_text(error_number, file))
    , error_number_(error_number)
{
}

bool WriteError::no_space() const noexcept { return error_number_ == ENOSPC || error_number_ == EDQUOT; }

std::string write_failure_text(std::string_view context, const std::exception& e)
{
    if (dynamic_cast<const WriteError*>(&e)) return e.what();
    return std::string(context) + e.what();
}

void write_file_bytes(const std::filesystem::path& file, std::string_view bytes, const std::filesystem::path& shown_as)
{
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) throw WriteError(errno, shown_as);
    int error_number = 0;
    for (std::size_t done = 0; done < bytes.size() && error_number == 0;) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) error_number = errno;
        else if (n == 0) error_number = EIO;
        else done += static_cast<std::size_t>(n);
    }
    if (error_number == 0 && ::fsync(fd) != 0 && errno != EINVAL) error_number = errno;  // EINVAL: no fsync here (a pipe)
    if (::close(fd) != 0 && error_number == 0 && errno != EINTR) error_number = errno;
    if (error_number != 0) throw WriteError(error_number, shown_as);
}

void sync_path(const std::filesystem::path& p)
{
    const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

void replace_file_atomically(
    const std::filesystem::path& path, const std::function<void(const std::filesystem::path& partial)>& write)
{
    std::filesystem::path partial = path;
    partial += ".partial";
    try {
        write(partial);
        sync_path(partial);
        std::filesystem::rename(partial, path);
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(partial, ignored);
        throw;
    }
    const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    sync_path(dir);
}

void write_text_file_atomically(const std::filesystem::path& path, std::string_view text)
{
    replace_file_atomically(
        path, [&](const std::filesystem::path& partial) { write_file_bytes(partial, text, path); });
}

} // namespace wiredem::engine::io
