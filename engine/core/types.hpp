// Basic value types shared by the whole engine: vectors, quaternions and the
// reference that names a body by (kind, index). Everything is SI.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>

namespace wiredem::engine {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

/// The kinds of moving bodies. The numeric order is the canonical order of
/// body references: grains first, then wire nodes, then membrane nodes.
enum class BodyKind : std::uint8_t { grain = 0, wire = 1, membrane = 2 };

inline constexpr int body_kind_count = 3;

/// Whether the contact stage advances the memory that integrates a step's
/// motion (each contact's tangential spring, δ_t += v_t δt, and its sliding
/// flag) or only evaluates the forces of the current state: begin_run
/// (step.hpp) keeps it, so that the first step advances it once.
enum class MemoryUpdate : std::uint8_t { commit, keep };

/// A body named by kind and index, packed into 32 bits (2 bits of kind, 30 of
/// index) so that comparing two references compares (kind, index).
struct BodyRef {
    std::uint32_t bits = 0;

    static constexpr std::uint32_t index_bits = 30;
    static constexpr std::uint32_t index_mask = (1u << index_bits) - 1u;
    /// Largest index a body of one kind can have.
    static constexpr std::uint32_t max_index = index_mask;

    constexpr BodyRef() = default;
    constexpr BodyRef(BodyKind kind, std::uint32_t index)
        : bits((static_cast<std::uint32_t>(kind) << index_bits) | (index & index_mask))
    {
    }
    [[nodiscard]] constexpr BodyKind kind() const { return static_cast<BodyKind>(bits >> index_bits); }
    [[nodiscard]] constexpr std::uint32_t index() const { return bits & index_mask; }
    friend constexpr bool operator==(BodyRef, BodyRef) = default;
    friend constexpr auto operator<=>(BodyRef a, BodyRef b) { return a.bits <=> b.bits; }
};

/// A wall as the second side of a contact: kind bits 3, past every BodyKind,
/// so that contact keys put every body–wall contact after every body pair.
[[nodiscard]] constexpr BodyRef wall_ref(std::uint32_t wall)
{
    BodyRef r;
    r.bits = (3u << BodyRef::index_bits) | (wall & BodyRef::index_mask);
    return r;
}
/// Whether a contact side names a wall (wall_ref) rather than a body.
[[nodiscard]] constexpr bool is_wall(BodyRef r) { return (r.bits >> BodyRef::index_bits) == 3u; }

/// Key of an unordered body pair: (kind of the smaller reference, kind of
/// the larger, smaller index, larger index) in 2 + 2 + 30 + 30 bits. Sorted
/// keys put the pairs of one pair of kinds together (grain–grain, grain–wire,
/// …), each group by (first, second): the contact kernel's blocks then
/// read every lane of a side from one kind's arrays.
[[nodiscard]] constexpr std::uint64_t pair_key(BodyRef a, BodyRef b)
{
    const BodyRef lo = a.bits < b.bits ? a : b, hi = a.bits < b.bits ? b : a;
    return static_cast<std::uint64_t>(lo.bits >> BodyRef::index_bits) << 62
         | static_cast<std::uint64_t>(hi.bits >> BodyRef::index_bits) << 60
         | static_cast<std::uint64_t>(lo.index()) << BodyRef::index_bits | hi.index();
}

} // namespace wiredem::engine
