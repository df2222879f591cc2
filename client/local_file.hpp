// Files the client writes on the user's machine (summaries, the report page).
#pragma once

#include "exit_codes.hpp"

#include "io/atomic_file.hpp"

#include <filesystem>
#include <string_view>

namespace wiredem::client {

/// Replaces `path` with `text` whole (engine::io::write_text_file_atomically);
/// a file that cannot be written is a CommandError with exit_code::local_io.
inline void write_local_file(const std::filesystem::path& path, std::string_view text)
{
    try {
        engine::io::write_text_file_atomically(path, text);
    } catch (const std::exception& e) {
        throw CommandError(exit_code::local_io, "cannot write " + path.string() + ": " + e.what());
    }
}

} // namespace wiredem::client
