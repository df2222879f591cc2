// UTF-8 as text from elsewhere arrives: what is a valid sequence, and text
// made valid by writing each byte that is not part of one as `\xNN`. The
// server echoes request headers and parameters in its JSON error messages,
// which must be valid UTF-8 (RFC 8259 §8.1); the client prints names and
// messages from the server on a terminal. Pure functions, header-only: the
// client's display library uses them without linking the api layer.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace wiredem::api {

/// Length (1–4) of the valid UTF-8 sequence that starts at s[i], and its code
/// point; 0 when the bytes there are not one: a continuation byte, a
/// truncated sequence, an overlong form, a surrogate or a code point above
/// U+10FFFF. Requires i < s.size().
[[nodiscard]] inline std::size_t utf8_sequence_at(std::string_view s, std::size_t i, char32_t& code_point)
{
    const auto b = static_cast<unsigned char>(s[i]);
    if (b < 0x80) {
        code_point = b;
        return 1;
    }
    // The length from the lead byte, every continuation 10xxxxxx.
    const std::size_t n = (b & 0xe0) == 0xc0 ? 2 : (b & 0xf0) == 0xe0 ? 3 : (b & 0xf8) == 0xf0 ? 4 : 0;
    if (n == 0 || i + n > s.size()) return 0;
    char32_t cp = n == 2 ? b & 0x1fu : n == 3 ? b & 0x0fu : b & 0x07u;
    for (std::size_t k = 1; k < n; ++k) {
        const auto c = static_cast<unsigned char>(s[i + k]);
        if ((c & 0xc0) != 0x80) return 0;
        cp = (cp << 6) | (c & 0x3fu);
    }
    // Overlong forms and surrogates are not UTF-8 either.
    if ((n == 2 && cp < 0x80) || (n == 3 && cp < 0x800) || (n == 4 && (cp < 0x10000 || cp > 0x10ffff))
        || (cp >= 0xd800 && cp <= 0xdfff))
        return 0;
    code_point = cp;
    return n;
}

/// `text` with every byte that is not part of a valid UTF-8 sequence written
/// as `\xNN`; valid text is returned unchanged.
[[nodiscard]] inline std::string valid_utf8(std::string_view text)
{
    std::string out;
    out.reserve(text.size());
    char32_t cp = 0;
    for (std::size_t i = 0; i < text.size();) {
        if (const std::size_t n = utf8_sequence_at(text, i, cp)) {
            out.append(text.substr(i, n));
            i += n;
            continue;
        }
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\x%02x", static_cast<unsigned char>(text[i]));
        out += buf;
        ++i;
    }
    return out;
}

/// `text` cut to at most `n` bytes at a UTF-8 character boundary.
[[nodiscard]] inline std::string cut_utf8(std::string text, std::size_t n)
{
    if (text.size() <= n) return text;
    while (n > 0 && (static_cast<unsigned char>(text[n]) & 0xC0) == 0x80) --n;
    text.resize(n);
    return text;
}

/// `text` made valid (valid_utf8) and bounded to about `max_bytes`: a longer
/// one is cut at a character boundary and ends "… (N bytes)", N its length
/// as given. What a reply echoes of a request (a path, a value, a header)
/// stays a line, however large the request.
[[nodiscard]] inline std::string bounded_echo(std::string_view text, std::size_t max_bytes)
{
    if (text.size() <= max_bytes)
        if (std::string whole = valid_utf8(text); whole.size() <= max_bytes) return whole;
    return cut_utf8(valid_utf8(text.substr(0, max_bytes)), max_bytes) + "… (" + std::to_string(text.size()) + " bytes)";
}

/// Number of Unicode code points in valid UTF-8.
[[nodiscard]] inline std::size_t utf8_length(std::string_view s)
{
    std::size_t n = 0;
    for (const char c : s) n += (static_cast<unsigned char>(c) & 0xC0u) != 0x80u;
    return n;
}

/// Whether valid UTF-8 `text` holds a control character: C0 (U+0000–U+001F),
/// DEL (U+007F) or C1 (U+0080–U+009F; U+009B is a terminal's CSI, which
/// starts an escape sequence as ESC [ does).
[[nodiscard]] inline bool has_control_character(std::string_view text)
{
    char32_t cp = 0;
    for (std::size_t i = 0; i < text.size();) {
        const std::size_t n = utf8_sequence_at(text, i, cp);
        if (n == 0) return true;  // not text at all
        if (cp < 0x20 || (cp >= 0x7f && cp <= 0x9f)) return true;
        i += n;
    }
    return false;
}

} // namespace wiredem::api
