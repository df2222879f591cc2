// The persistent list of body pairs that may touch (a Verlet neighbour list),
// with each pair's tangential spring and this step's forces.
//
// Pairs are sorted by pair_key (smaller body first), so iterating them is
// canonical. A pair's slot is written by exactly one thread per step. The list
// is rebuilt only when some body has moved more than half the skin since the
// last build; a rebuild carries each surviving pair's tangential state across
// by a merge of the two sorted key lists. The incidence list (CSR over flat body
// index, ascending pair index) lets every body gather its pair forces in a
// fixed order.
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

struct ContactList {
    std::vector<std::uint64_t> key;          ///< pair_key(a, b), ascending
    std::vector<BodyRef> first, second;       ///< a < b
    std::vector<std::uint32_t> flat_first, flat_second; ///< flat body indices of a, b
    std::vector<TangentialState> tangential;  ///< spring memory; reset when the contact opens
    std::vector<Vec3> force_n;                ///< this step's force on a (−force on b) [N]
    std::vector<Vec3> torque_first_n_m;       ///< torque on a [N·m]
    std::vector<Vec3> torque_second_n_m;      ///< torque on b [N·m]
    std::vector<double> normal_force_n;       ///< |F_n| this step, 0 when apart [N]
    std::vector<std::uint8_t> touching;       ///< 1 when overlapping this step

    std::vector<std::uint32_t> incidence_start; ///< CSR offsets per flat body, size bodies + 1
    std::vector<Incidence> incidence;

    [[nodiscard]] std::size_t size() const { return key.size(); }

    /// Replaces the pair set with `pairs` (flat indices, sorted by key), keeping
    /// the tangential state of pairs present in both, and rebuilds the incidence
    /// list for `flat_body_count` bodies.
    void rebuild(const std::vector<std::uint64_t>& new_keys, const std::vector<BodyRef>& new_first,
        const std::vector<BodyRef>& new_second, const std::vector<std::uint32_t>& new_flat_first,
        const std::vector<std::uint32_t>& new_flat_second, std::size_t flat_body_count);
};

} // namespace wiredem::engine
