// Files that are replaced whole: a reader, or a run that is killed or loses
// power at any point, finds the old file or the whole new one, never part
// of one. Every file the engine, the campaign and the server publish is
// written through replace_file_atomically.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace wiredem::engine::io {

/// A file that could not be written: what() is one line naming the system's
/// reason and the file, e.g. "no space left on device writing out/result.h5"
/// (a full disk is the case met in practice; the job's error is this line).
class WriteError : public std::runtime_error {
public:
    /// @param error_number  the errno of the failing call
    /// @param file          the file as the user knows it (not its ".partial")
    WriteError(int error_number, const std::filesystem::path& file);
    /// The errno of the failing call.
    [[nodiscard]] int error_number() const noexcept { return error_number_; }
    /// Whether the file system is full (ENOSPC) or the user's quota used up
    /// (EDQUOT): a condition that passes once space is freed.
    [[nodiscard]] bool no_space() const noexcept;

private:
    int error_number_;
};

/// An error message for a failed write: a WriteError's own line as it is
/// (it names the file and the reason already), anything else after `context`.
[[nodiscard]] std::string write_failure_text(std::string_view context, const std::exception& e);

/// Writes `bytes` to `file` (created or truncated) and flushes them to the
/// disk (fsync), checking every call, the fsync and the close included (a
/// full disk may show only there). @throws WriteError naming `shown_as`.
void write_file_bytes(const std::filesystem::path& file, std::string_view bytes, const std::filesystem::path& shown_as);

/// Flushes a file's or a directory's data to the disk (fsync). Best effort:
/// some file systems refuse a directory's, and a path that cannot be opened
/// is left alone.
void sync_path(const std::filesystem::path& p);

/// Replaces `path` with what `write` puts in the file it is given (`path`
/// with ".partial" appended): that file is flushed to the disk, renamed onto
/// `path` (POSIX rename replaces an existing file atomically) and the
/// directory flushed, so the rename survives a crash too. On an exception
/// the partial file is removed and the exception passes on.
void replace_file_atomically(
    const std::filesystem::path& path, const std::function<void(const std::filesystem::path& partial)>& write);

/// replace_file_atomically with `text` as the file's bytes; throws
/// WriteError naming `path` when it cannot be written.
void write_text_file_atomically(const std::filesystem::path& path, std::string_view text);

} // namespace wiredem::engine::io
