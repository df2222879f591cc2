// Files that are replaced whole: a reader, or a run that is killed or loses
// power at any point, finds the old file or the whole new one, never part
// of one. Every file the engine, the campaign and the server publish is
// written through replace_file_atomically.
#pragma once

#include <filesystem>
#include <functional>
#include <string_view>

namespace wiredem::engine::io {

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
/// std::runtime_error naming the file when it cannot be written.
void write_text_file_atomically(const std::filesystem::path& path, std::string_view text);

} // namespace wiredem::engine::io
