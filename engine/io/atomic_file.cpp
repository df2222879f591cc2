#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <stdexcept>

namespace wiredem::engine::io {

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
    replace_file_atomically(path, [&](const std::filesystem::path& partial) {
        std::ofstream out(partial, std::ios::binary | std::ios::trunc);
        out.write(text.data(), static_cast<std::streamsize>(text.size()));
        out.close();
        if (!out) throw std::runtime_error("cannot write " + partial.string());
    });
}

} // namespace wiredem::engine::io
