// FNV-1a over raw bytes: a cheap fingerprint, used by state_hash
// (state/state_hash.hpp) to check that runs are bit-identical.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace wiredem::engine {

/// Incremental 64-bit FNV-1a hash.
class Fnv1a {
public:
    void add_bytes(const void* data, std::size_t n)
    {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < n; ++i) {
            h_ ^= p[i];
            h_ *= 0x100000001b3ull;
        }
    }
    template <class T>
    void add(const std::vector<T>& v)
    {
        if (!v.empty()) add_bytes(v.data(), v.size() * sizeof(T));
    }
    [[nodiscard]] std::uint64_t value() const { return h_; }

private:
    std::uint64_t h_ = 0xcbf29ce484222325ull;
};

} // namespace wiredem::engine
