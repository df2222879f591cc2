// A Boost.JSON basic_parser handler that builds a value like json::parser
// does, but converts floating-point numbers with std::from_chars (correctly
// rounded) and rejects duplicate keys.
#include "api/json_text.hpp"

#include <boost/json/basic_parser_impl.hpp>
#include <boost/json/serialize.hpp>
#include <boost/json/value_stack.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace wiredem::api {

namespace {

namespace json = boost::json;

/// Handler for json::basic_parser: forwards to a value_stack (as Boost's own
/// parser does) and keeps the text of numbers and keys that arrive in parts.
struct StrictHandler {
    static constexpr std::size_t max_object_size = json::object::max_size();
    static constexpr std::size_t max_array_size = json::array::max_size();
    static constexpr std::size_t max_key_size = json::string::max_size();
    static constexpr std::size_t max_string_size = json::string::max_size();

    json::value_stack st;
    std::string number_text;                   ///< parts of the current number
    std::string key_text;                      ///< parts of the current key
    std::vector<std::vector<std::string>> keys; ///< keys seen in each open object
    std::string duplicate_key;                 ///< set when parsing stopped on a duplicate

    bool on_document_begin(json::error_code&) { return true; }
    bool on_document_end(json::error_code&) { return true; }
    bool on_object_begin(json::error_code&)
    {
        keys.emplace_back();
        return true;
    }
    bool on_object_end(std::size_t n, json::error_code&)
    {
        keys.pop_back();
        st.push_object(n);
        return true;
    }
    bool on_array_begin(json::error_code&) { return true; }
    bool on_array_end(std::size_t n, json::error_code&)
    {
        st.push_array(n);
        return true;
    }
    bool on_key_part(json::string_view s, std::size_t, json::error_code&)
    {
        key_text.append(s.data(), s.size());
        st.push_chars(s);
        return true;
    }
    bool on_key(json::string_view s, std::size_t, json::error_code& ec)
    {
        key_text.append(s.data(), s.size());
        // Objects in a job spec have a few dozen keys: a linear scan is fine.
        for (const std::string& k : keys.back())
            if (k == key_text) {
                duplicate_key = key_text;
                ec = json::error::syntax; // stops the parser; the message is ours
                return false;
            }
        keys.back().push_back(key_text);
        key_text.clear();
        st.push_key(s);
        return true;
    }
    bool on_string_part(json::string_view s, std::size_t, json::error_code&)
    {
        st.push_chars(s);
        return true;
    }
    bool on_string(json::string_view s, std::size_t, json::error_code&)
    {
        st.push_string(s);
        return true;
    }
    bool on_number_part(json::string_view s, json::error_code&)
    {
        number_text.append(s.data(), s.size());
        return true;
    }
    bool on_int64(std::int64_t i, json::string_view, json::error_code&)
    {
        number_text.clear();
        st.push_int64(i);
        return true;
    }
    bool on_uint64(std::uint64_t u, json::string_view, json::error_code&)
    {
        number_text.clear();
        st.push_uint64(u);
        return true;
    }
    bool on_double(double d, json::string_view s, json::error_code&)
    {
        number_text.append(s.data(), s.size());
        double exact = 0.0;
        const char* first = number_text.data();
        const char* last = first + number_text.size();
        const auto [end, err] = std::from_chars(first, last, exact);
        // Out of range (1e400): keep Boost's value (±inf or 0); validation
        // rejects what does not fit a field.
        st.push_double(err == std::errc{} && end == last ? exact : d);
        number_text.clear();
        return true;
    }
    bool on_bool(bool b, json::error_code&)
    {
        st.push_bool(b);
        return true;
    }
    bool on_null(json::error_code&)
    {
        st.push_null();
        return true;
    }
    bool on_comment_part(json::string_view, json::error_code&) { return true; }
    bool on_comment(json::string_view, json::error_code&) { return true; }
};

/// "line L, column C (byte B)" for a byte offset; lines and columns count from 1,
/// columns in bytes.
std::string position_text(std::string_view text, std::size_t offset)
{
    std::size_t line = 1, line_start = 0;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i)
        if (text[i] == '\n') {
            ++line;
            line_start = i + 1;
        }
    return "line " + std::to_string(line) + ", column " + std::to_string(offset - line_start + 1) + " (byte "
         + std::to_string(offset) + ")";
}

bool has_non_finite(const json::value& v)
{
    switch (v.kind()) {
    case json::kind::double_: return !std::isfinite(v.get_double());
    case json::kind::array:
        return std::any_of(v.get_array().begin(), v.get_array().end(), [](const json::value& e) { return has_non_finite(e); });
    case json::kind::object:
        return std::any_of(v.get_object().begin(), v.get_object().end(),
            [](const json::key_value_pair& e) { return has_non_finite(e.value()); });
    default: return false;
    }
}

void null_non_finite(json::value& v)
{
    switch (v.kind()) {
    case json::kind::double_:
        if (!std::isfinite(v.get_double())) v = nullptr;
        break;
    case json::kind::array:
        for (json::value& e : v.get_array()) null_non_finite(e);
        break;
    case json::kind::object:
        for (json::key_value_pair& e : v.get_object()) null_non_finite(e.value());
        break;
    default: break;
    }
}

} // namespace

std::string json_document_text(const json::value& document)
{
    if (!has_non_finite(document)) return json::serialize(document);  // the usual case: no copy
    json::value copy = document;
    null_non_finite(copy);
    return json::serialize(copy);
}

engine::Result<json::value, std::string> parse_json_text(std::string_view text)
{
    json::parse_options options; // strict: no comments, no trailing commas, valid UTF-8
    json::basic_parser<StrictHandler> parser(options);
    parser.handler().st.reset();
    json::error_code ec;
    const std::size_t consumed = parser.write_some(false, text.data(), text.size(), ec);
    if (ec) {
        StrictHandler& h = parser.handler();
        if (!h.duplicate_key.empty())
            return engine::Err{"duplicate key \"" + h.duplicate_key + "\" at " + position_text(text, consumed)};
        return engine::Err{ec.message() + " at " + position_text(text, consumed)};
    }
    if (consumed < text.size())
        return engine::Err{"unexpected text after the JSON document at " + position_text(text, consumed)};
    return parser.handler().st.release();
}

} // namespace wiredem::api
