// UTF-8 as text from elsewhere arrives: what is a valid sequence, and text
// made valid by writing each byte that is not part of one as `\xNN`. The
// server echoes request headers and parameters in its JSON error messages,
// which must be valid UTF-8 (RFC 8259 §8.1); the client prints names and
// messages from the server on a terminal. Pure functions.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace wiredem::api {

/// Length (1–4) of the valid UTF-8 sequence that starts at s[i], and its code
/// point; 0 when the bytes there are not one: a continuation byte, a
/// truncated sequence, an overlong form, a surrogate or a code point above
/// U+10FFFF. Requires i < s.size().
[[nodiscard]] std::size_t utf8_sequence_at(std::string_view s, std::size_t i, char32_t& code_point);

/// `text` with every byte that is not part of a valid UTF-8 sequence written
/// as `\xNN`; valid text is returned unchanged.
[[nodiscard]] std::string valid_utf8(std::string_view text);

} // namespace wiredem::api
