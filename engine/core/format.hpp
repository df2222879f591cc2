// Numbers in messages, labels and tables, written one way everywhere (engine,
// api, server, campaign, client, report): a derived quantity to a few
// significant digits, a value a user gave exactly as it reads back, a table's
// column to fixed decimals. The one number formatter of the tree: header-only
// and on the standard library alone, so that every layer can include it (the
// client's display library, which links no engine, includes it by path).
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

/// `v` with `decimals` digits after the point, as printf's %.*f writes it
/// ("12.3", "100", "0.050"): for a table's columns and a duration.
[[nodiscard]] inline std::string fixed_number(double v, int decimals)
{
    std::array<char, 352> buf{}; // %f of the largest double: 309 digits before the point
    const int n = std::snprintf(buf.data(), buf.size(), "%.*f", decimals, v);
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
