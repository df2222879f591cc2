// Numbers in messages and labels, written one way everywhere (engine, api,
// server, campaign): a derived quantity to a few significant digits, a value
// a user gave exactly as it reads back.
#pragma once

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdio>
#include <string>

namespace wiredem::engine {

/// `v` with `digits` significant digits, as printf's %g writes it
/// ("1.88e-07", "0.1", "2e+04"): for derived quantities.
[[nodiscard]] inline std::string format_number(double v, int digits = 3)
{
    std::array<char, 48> buf{};
    const int n = std::snprintf(buf.data(), buf.size(), "%.*g", digits, v);
    return std::string(buf.data(), static_cast<std::size_t>(std::clamp(n, 0, static_cast<int>(buf.size()) - 1)));
}

/// The shortest text that reads back as the same double ("1e-05", "0.1",
/// "20000"): shows users exactly the value they gave.
[[nodiscard]] inline std::string exact_number(double v)
{
    std::array<char, 64> buf{};
    const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    return std::string(buf.data(), res.ptr);
}

} // namespace wiredem::engine
