// A job's files, DATA_DIR/jobs/{id}/…, reached without following symbolic
// links: each component below the data directory is opened with
// O_NOFOLLOW relative to its parent (openat), so a symlink planted in the
// data directory (jobs/{id} → /etc, result.h5 → ~/.ssh/id_rsa,
// work/job.json → any file) can neither redirect a download nor a write:
// the open fails instead. The data directory itself is the operator's
// choice and is trusted.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace wiredem::server {

/// The largest summary.json the server takes from a runner and serves [bytes]
/// (a runner's is a few KiB).
inline constexpr std::size_t max_summary_bytes = 16u << 20;

/// An owned file descriptor (-1: none), closed on destruction.
class UniqueFd {
public:
    UniqueFd() = default;
    explicit UniqueFd(int fd) : fd_(fd) {}
    ~UniqueFd();
    UniqueFd(UniqueFd&& o) noexcept : fd_(o.release()) {}
    UniqueFd& operator=(UniqueFd&& o) noexcept;
    UniqueFd(const UniqueFd&) = delete;
    UniqueFd& operator=(const UniqueFd&) = delete;
    [[nodiscard]] int get() const { return fd_; }
    [[nodiscard]] explicit operator bool() const { return fd_ >= 0; }
    /// Gives up ownership.
    int release() { return std::exchange(fd_, -1); }

private:
    int fd_ = -1;
};

/// Opens DATA_DIR/jobs/{id}/{name} (`name` one plain file name) for reading.
/// Empty (errno set) when it is missing, is not a regular file, or any
/// component is a symlink. `id` must have passed is_valid_job_id.
[[nodiscard]] UniqueFd open_job_file(const std::filesystem::path& data_dir, std::string_view id, std::string_view name);

/// The file's bytes, when it is a regular file of at most `max_bytes`
/// reached as open_job_file reaches it.
[[nodiscard]] std::optional<std::string> read_job_file(
    const std::filesystem::path& data_dir, std::string_view id, std::string_view name, std::size_t max_bytes);

/// Writes (creating or truncating) DATA_DIR/jobs/{id}/{relative}, `relative`
/// being "name" or "work/name", creating the folders on the way; nothing on
/// the way may be a symlink. @throws std::runtime_error naming the path.
void write_job_file(const std::filesystem::path& data_dir, std::string_view id, std::string_view relative,
    std::string_view text);

/// Creates DATA_DIR/jobs/{id}/work/out (what exists already is kept: an
/// earlier attempt's work folder is continued from) as real folders, none
/// of them a symlink, and returns DATA_DIR/jobs/{id}/work.
/// @throws std::runtime_error naming the path.
std::filesystem::path make_work_dir(const std::filesystem::path& data_dir, std::string_view id);

/// Removes DATA_DIR/jobs/{id} with everything in it (a symlink in it is
/// removed, never followed). Best effort; returns false when something stays.
bool remove_job_dir(const std::filesystem::path& data_dir, std::string_view id);

} // namespace wiredem::server
