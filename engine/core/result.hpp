// A minimal Result<T, E> for fallible set-up code (C++20 has no std::expected).
#pragma once

#include <utility>
#include <variant>

namespace wiredem::engine {

/// Wraps an error value so that Result can be built from it unambiguously.
/// The constructor lets `Err(x)` compile on clang 14 too, which lacks C++20's
/// parenthesized initialization of aggregates (P0960).
template <class E>
struct Err {
    explicit Err(E v) : value(std::move(v)) {}
    E value;
};
template <class E>
Err(E) -> Err<E>;

/// Either a value or an error. Accessing the wrong alternative is a
/// programming error (std::bad_variant_access).
template <class T, class E>
class Result {
public:
    Result(T value) : v_(std::in_place_index<0>, std::move(value)) {}
    template <class U>
    Result(Err<U> e) : v_(std::in_place_index<1>, E(std::move(e.value)))
    {
    }

    [[nodiscard]] bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }

    [[nodiscard]] T& value() & { return std::get<0>(v_); }
    [[nodiscard]] const T& value() const& { return std::get<0>(v_); }
    [[nodiscard]] T&& value() && { return std::get<0>(std::move(v_)); }
    [[nodiscard]] const E& error() const { return std::get<1>(v_); }

private:
    std::variant<T, E> v_;
};

} // namespace wiredem::engine
