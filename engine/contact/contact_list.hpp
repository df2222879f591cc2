// The persistent list of body pairs that may touch (a Verlet neighbour list),
// with each pair's tangential spring and this step's forces.
//
// Pairs are sorted by pair_key (smaller body first), so iterating them is
// canonical. A pair's slot is written by exactly one thread per step. The list
// is rebuilt only when some body has moved more than half the skin since the
// last build; a rebuild carries each surviving pair's tangential state across
// by a merge of the two sorted key lists. The incidence list (CSR over flat body
// index, ascending pair index) lets every body gather its pair forces in a
// fixed order; the pair loop writes each force straight into the two bodies'
// incidence slots, so the gather reads memory in order.
#pragma once

#include "core/types.hpp"
#include "laws/tangential.hpp"

#include <cstdint>
#include <vector>

namespace wiredem::engine {

/// One body's link to a pair: pair index and whether the body is the pair's
/// first member (a) or second (b).
struct Incidence {
    std::uint32_t pair = 0;
    bool is_first = true;
};

/// A pair's force and torque on one of its two bodies, stored where that
/// body's gather reads it: shares[e] belongs to incidence[e].
struct ContactShare {
    Vec3 force_n = Vec3::Zero();    ///< [N]
    Vec3 torque_n_m = Vec3::Zero(); ///< [N·m]
};

struct ContactList {
    std::vector<std::uint64_t> key;          ///< pair_key(a, b), ascending
    std::vector<BodyRef> first, second;       ///< a < b
    std::vector<std::uint32_t> flat_first, flat_second; ///< flat body indices of a, b
    /// (4/3) E* √R* of the pair, set with the pair (materials and radii are fixed) [N/m^{3/2}]
    std::vector<double> hertz_coefficient;
    std::vector<TangentialState> tangential;  ///< spring memory; reset when the contact opens
    std::vector<Vec3> force_n;                ///< this step's force on a (−force on b) [N]
    std::vector<double> normal_force_n;       ///< |F_n| this step, 0 when apart [N]
    std::vector<std::uint8_t> touching;       ///< 1 when overlapping this step

    std::vector<std::uint32_t> incidence_start; ///< CSR offsets per flat body, size bodies + 1
    std::vector<Incidence> incidence;
    /// This step's force and torque on each body of each pair, in incidence
    /// order: the pair loop writes a pair's two shares (one writer per slot),
    /// and each body's gather then reads its own shares contiguously, in
    /// ascending pair order. Zero while the pair is apart.
    std::vector<ContactShare> shares;
    std::vector<std::uint32_t> share_of_first, share_of_second; ///< per pair: slot in shares

    [[nodiscard]] std::size_t size() const { return key.size(); }

    /// Replaces the pair set with `pairs` (flat indices, sorted by key), keeping
    /// the tangential state of pairs present in both, and rebuilds the incidence
    /// list for `flat_body_count` bodies.
    void rebuild(const std::vector<std::uint64_t>& new_keys, const std::vector<BodyRef>& new_first,
        const std::vector<BodyRef>& new_second, const std::vector<std::uint32_t>& new_flat_first,
        const std::vector<std::uint32_t>& new_flat_second, std::size_t flat_body_count);
};

} // namespace wiredem::engine
