// One table of names per enum of the engine's inputs: the names a job spec
// writes (api/job_spec.cpp reads and writes JSON through these tables, so the
// door's vocabulary is the engine's own) and the engine's own messages and
// result files. Header-only, constexpr, no dependencies.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>
#include <utility>

namespace wiredem::engine {

/// Each value of E with its name, in the enum's order.
template <class E, std::size_t N>
using NameTable = std::array<std::pair<std::string_view, E>, N>;

/// The name of `value` in `table`; "?" for a value not in it.
template <class E, std::size_t N>
[[nodiscard]] constexpr std::string_view name_in(const NameTable<E, N>& table, E value) noexcept
{
    for (const auto& [name, v] : table)
        if (v == value) return name;
    return "?";
}

/// The value named `name` in `table`, if any (exact, case-sensitive).
template <class E, std::size_t N>
[[nodiscard]] constexpr std::optional<E> value_named(const NameTable<E, N>& table, std::string_view name) noexcept
{
    for (const auto& [n, v] : table)
        if (n == name) return v;
    return std::nullopt;
}

} // namespace wiredem::engine
