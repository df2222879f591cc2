// Job files through openat(…, O_NOFOLLOW), one component at a time.
#include "job_files.hpp"

#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace wiredem::server {
namespace fs = std::filesystem;

UniqueFd::~UniqueFd()
{
    if (fd_ >= 0) ::close(fd_);
}

UniqueFd& UniqueFd::operator=(UniqueFd&& o) noexcept
{
    if (this != &o) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = o.release();
    }
    return *this;
}

namespace {

constexpr int dir_flags = O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC;

/// The folder `name` in `parent`, created first when `create` (mode 0777
/// less the umask: main() sets one that keeps other users out).
UniqueFd open_dir_at(int parent, const std::string& name, bool create)
{
    if (create && ::mkdirat(parent, name.c_str(), 0777) != 0 && errno != EEXIST) return UniqueFd();
    return UniqueFd(::openat(parent, name.c_str(), dir_flags));
}

[[noreturn]] void fail(const std::string& what, const fs::path& path)
{
    const int err = errno;
    // A full disk: one line the router answers with 507 and a worker waits on.
    if (err == ENOSPC || err == EDQUOT) throw engine::io::WriteError(err, path);
    throw std::runtime_error("cannot " + what + " " + path.string() + ": "
                             + (err == ELOOP || err == ENOTDIR ? std::string("it is a symbolic link or not a folder")
                                                               : std::string(std::strerror(err))));
}

/// DATA_DIR/jobs/{id}, optionally created.
UniqueFd open_job_dir(const fs::path& data_dir, std::string_view id, bool create)
{
    const UniqueFd data(::open(data_dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (!data) return UniqueFd();
    const UniqueFd jobs = open_dir_at(data.get(), "jobs", create);
    if (!jobs) return UniqueFd();
    return open_dir_at(jobs.get(), std::string(id), create);
}

} // namespace

UniqueFd open_job_file(const fs::path& data_dir, std::string_view id, std::string_view name)
{
    const UniqueFd dir = open_job_dir(data_dir, id, false);
    if (!dir) return UniqueFd();
    UniqueFd fd(::openat(dir.get(), std::string(name).c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK));
    struct stat st{};
    if (!fd || ::fstat(fd.get(), &st) != 0) return UniqueFd();
    if (!S_ISREG(st.st_mode)) {  // a FIFO would block a reader; O_NONBLOCK keeps the open itself from blocking
        errno = EINVAL;
        return UniqueFd();
    }
    return fd;
}

std::optional<std::string> read_job_file(
    const fs::path& data_dir, std::string_view id, std::string_view name, std::size_t max_bytes)
{
    const UniqueFd fd = open_job_file(data_dir, id, name);
    struct stat st{};
    if (!fd || ::fstat(fd.get(), &st) != 0 || static_cast<std::uint64_t>(st.st_size) > max_bytes) return std::nullopt;
    std::string text(static_cast<std::size_t>(st.st_size), '\0');
    std::size_t got = 0;
    while (got < text.size()) {
        const ssize_t n = ::read(fd.get(), text.data() + got, text.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return std::nullopt;
        got += static_cast<std::size_t>(n);
    }
    return text;
}

void write_job_file(const fs::path& data_dir, std::string_view id, std::string_view relative, std::string_view text)
{
    const fs::path shown = data_dir / "jobs" / std::string(id) / std::string(relative);
    UniqueFd dir = open_job_dir(data_dir, id, true);
    if (!dir) fail("open the folder of", shown);
    std::string name(relative);
    if (const auto slash = name.find('/'); slash != std::string::npos) {
        dir = open_dir_at(dir.get(), name.substr(0, slash), true);
        if (!dir) fail("open the folder of", shown);
        name = name.substr(slash + 1);
    }
    const UniqueFd fd(::openat(dir.get(), name.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666));
    if (!fd) fail("write", shown);
    for (std::size_t done = 0; done < text.size();) {
        const ssize_t n = ::write(fd.get(), text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) fail("write", shown);
        done += static_cast<std::size_t>(n);
    }
}

fs::path make_work_dir(const fs::path& data_dir, std::string_view id)
{
    const fs::path work = data_dir / "jobs" / std::string(id) / "work";
    const UniqueFd job = open_job_dir(data_dir, id, true);
    if (!job) fail("create", work.parent_path());
    const UniqueFd w = open_dir_at(job.get(), "work", true);
    if (!w) fail("create", work);
    if (!open_dir_at(w.get(), "out", true)) fail("create", work / "out");
    return work;
}

bool remove_job_dir(const fs::path& data_dir, std::string_view id)
{
    // remove_all unlinks a symlink it meets, never follows one; only the
    // path to the job folder must be checked (a `jobs` symlink would be followed).
    // A worker may still be removing the job's work folder (it does so just
    // after the store says the job ended): what vanishes meanwhile fails
    // one pass, which the next completes.
    std::error_code ec;
    if (fs::is_symlink(data_dir / "jobs", ec)) return false;
    const fs::path dir = data_dir / "jobs" / std::string(id);
    for (int pass = 0; pass < 3; ++pass) {
        fs::remove_all(dir, ec);
        if (!ec) return true;
    }
    return !fs::exists(fs::symlink_status(dir, ec));
}

} // namespace wiredem::server
