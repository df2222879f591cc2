// External forces on single bodies (Model::point_loads): a test's tip load, a
// column test's wire weight under mass scaling (one per wire node).
//
// Invariant: the loads are sorted by BodyRef (grains, then wire nodes, then
// membrane nodes, each by index) and name each body at most once. Every way
// to write the list keeps it (set, from_sorted), so the gather adds a body's
// load right after its contacts' sum, in the block of bodies that owns it and
// on that block's thread (step.cpp, gather_forces), with no check per step:
// a body's force is f + p, the same bits for any thread count.
#pragma once

#include "core/result.hpp"
#include "core/types.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace wiredem::engine {

/// The point loads of a World: sorted by body, each body at most once.
/// Not thread-safe to write; reading from several threads is.
class PointLoads {
public:
    /// A body and the force on it [N].
    using Load = std::pair<BodyRef, Vec3>;

    PointLoads() = default;

    /// The loads of `list`, which must be sorted by body (BodyRef order) and
    /// name each body at most once; else an error that names the first entry
    /// out of order and the one before it (a file written by another program,
    /// or edited: io/snapshot.cpp).
    [[nodiscard]] static Result<PointLoads, std::string> from_sorted(std::vector<Load> list);

    /// Sets the force on `body` [N]: inserted in its place, or replacing the
    /// body's load. O(log size()) when `body` follows every listed body (a
    /// list built in body order), else O(size()).
    void set(BodyRef body, const Vec3& force_n);
    /// Removes every load.
    void clear() noexcept
    {
        loads_.clear();
        kind_start_.fill(0);
    }
    /// Makes room for `n` loads.
    void reserve(std::size_t n) { loads_.reserve(n); }

    /// The loads on bodies of `kind` with an index in [begin, end), in body
    /// order. O(1) where the kind's loads name consecutive bodies (the
    /// wire's weight: every node), else O(log size()).
    [[nodiscard]] std::span<const Load> of(BodyKind kind, std::uint32_t begin, std::uint32_t end) const;

    /// The whole list, in body order.
    [[nodiscard]] const std::vector<Load>& list() const noexcept { return loads_; }
    [[nodiscard]] std::size_t size() const noexcept { return loads_.size(); }
    [[nodiscard]] bool empty() const noexcept { return loads_.empty(); }
    [[nodiscard]] const Load& operator[](std::size_t i) const { return loads_[i]; }
    [[nodiscard]] std::vector<Load>::const_iterator begin() const noexcept { return loads_.begin(); }
    [[nodiscard]] std::vector<Load>::const_iterator end() const noexcept { return loads_.end(); }

private:
    /// Where each kind's loads start in the list; the last entry, where the
    /// last kind's end (loads on walls, which no step adds, sort after it).
    void index_kinds() noexcept;

    std::vector<Load> loads_;
    std::array<std::uint32_t, body_kind_count + 1> kind_start_{};
};

} // namespace wiredem::engine
