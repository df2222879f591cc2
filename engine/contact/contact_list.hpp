// The persistent list of contacts that may touch before the next rebuild (a
// Verlet neighbour list): body pairs and body–wall contacts, each stored once,
// with its tangential spring and this step's force.
//
// A contact has two sides: `first` is always a body; `second` is a later body
// (a pair) or a wall (wall_ref). Contacts are sorted by contact_key: every
// pair grouped by the kinds of its bodies (grain–grain, grain–wire, …) and
// by (first, second) within a group (pair_key), then every wall contact by
// (wall, body), so iterating them is canonical, a wall's contacts are
// consecutive and a block of contacts reads each side from one kind. A
// contact's slot is written by exactly one thread per step. The list is
// rebuilt only when some body or wall has moved more than half the skin since
// the last build; a rebuild carries each surviving contact's tangential state
// across by a merge of the two sorted key lists. So a wall's memory is O(its
// contacts), not O(bodies).
//
// The incidence list (CSR over flat body index, ascending contact index) lets
// every body gather its contact forces in a fixed order: its pairs, then its
// walls in wall order. The kernel writes each contact's force once; the
// gather reads it for both bodies (with its sign) and forms each body's
// torque from the contact's n × F_t and the body's own lever arm.
#pragma once

#include "core/types.hpp"
#include "laws/tangential.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace wiredem::engine {

/// Sort key of a contact: pair_key for two bodies; (wall, body) for a wall.
[[nodiscard]] constexpr std::uint64_t contact_key(BodyRef first, BodyRef second)
{
    if (is_wall(second)) return (static_cast<std::uint64_t>(second.bits) << 32) | first.bits;
    return pair_key(first, second);
}

/// One body's link to a contact: contact index and whether the body is the
/// contact's first side (a) or second (b), in 32 bits.
struct Incidence {
    std::uint32_t bits = 0; ///< contact · 2 + (1 if the body is second)

    Incidence() = default;
    Incidence(std::uint32_t contact_index, bool is_first) : bits(contact_index << 1 | (is_first ? 0u : 1u)) {}
    [[nodiscard]] std::uint32_t contact() const { return bits >> 1; }
    /// 0 if the body is first, 1 if second.
    [[nodiscard]] std::uint32_t side() const { return bits & 1u; }
    [[nodiscard]] bool is_first() const { return side() == 0; }
    /// +1 for first, −1 for second: the sign of the contact's force on the body.
    [[nodiscard]] double sign() const { return 1.0 - 2.0 * static_cast<double>(side()); }
};

/// Flat index of the first body of each kind (grains, wire, membrane) and,
/// last, the number of bodies.
using FlatOffsets = std::array<std::uint32_t, body_kind_count + 1>;

/// What the kernel writes for a contact every step, in one 64-byte record:
/// the gather reads one cache line per contact of a body instead of three
/// (force, n × F_t and overlap from separate arrays), and the AVX-512 kernel
/// writes a lane's record with one store. Two halves of four doubles: the
/// force with the overlap, n × F_t with |F_n|, so a 256-bit load brings a
/// vector with what multiplies it (the AVX2 gather). All zero while apart.
struct alignas(64) ContactOutput {
    Vec3 force_n = Vec3::Zero();   ///< this step's force on `first` (−force on a body `second`) [N]
    double overlap_m = 0.0;        ///< ξ this step, while touching [m]
    /// n × F_t this step (n from first to second): a body's torque from the
    /// contact is its lever arm r − ξ/2 times this [N].
    Vec3 normal_x_tangential_n = Vec3::Zero();
    double normal_force_n = 0.0;   ///< |F_n| this step [N]
};
static_assert(sizeof(ContactOutput) == 64 && offsetof(ContactOutput, overlap_m) == 3 * sizeof(double)
              && offsetof(ContactOutput, normal_x_tangential_n) == 4 * sizeof(double)
              && offsetof(ContactOutput, normal_force_n) == 7 * sizeof(double));

struct ContactList {
    std::vector<BodyRef> first, second;       ///< see the top; sorted by contact_key
    /// (4/3) E* √R* of the contact, set at the rebuild (materials and radii
    /// are fixed; R* = r against a wall) [N/m^{3/2}]
    std::vector<double> hertz_coefficient;
    std::vector<TangentialState> tangential;  ///< spring memory; reset when the contact opens
    /// Rolling springs θ_r [rad] (laws/rolling.hpp): memory like the
    /// tangential springs', kept only while the rolling law is on (sized
    /// with the list then, empty otherwise); reset when the contact opens.
    std::vector<Vec3> rolling_rad;
    /// This step's rolling torque on `first` (−it on a body `second`) [N·m];
    /// sized as rolling_rad. Zero for a contact that does not roll (apart,
    /// or not grain–grain or grain–wall).
    std::vector<Vec3> rolling_torque_n_m;
    std::vector<ContactOutput> output;        ///< this step's force, n × F_t, overlap and |F_n|
    std::vector<std::uint8_t> touching;       ///< 1 when overlapping this step
    /// Contacts [0, pair_count) are body pairs; wall i's contacts are
    /// [wall_start[i], wall_start[i + 1]), with wall_start[0] = pair_count.
    std::vector<std::uint32_t> wall_start;

    std::vector<std::uint32_t> incidence_start; ///< CSR offsets per flat body, size bodies + 1
    std::vector<Incidence> incidence;

    [[nodiscard]] std::size_t size() const { return first.size(); }
    /// Number of body pairs (they come first).
    [[nodiscard]] std::size_t pair_count() const { return wall_start.empty() ? size() : wall_start.front(); }

    /// Index of the contact (first, second), if it is in the list; `second`
    /// may be a wall_ref.
    [[nodiscard]] std::optional<std::size_t> find(BodyRef first_side, BodyRef second_side) const;

    /// Contact p is apart: its spring, outputs and touching flag go back to
    /// zero (what every slot of a contact apart holds).
    void release(std::size_t p)
    {
        tangential[p] = TangentialState{};
        output[p] = ContactOutput{};
        touching[p] = 0;
        if (!rolling_rad.empty()) rolling_rad[p] = rolling_torque_n_m[p] = Vec3::Zero();
    }

    /// Whether the list keeps rolling springs (rolling_rad).
    [[nodiscard]] bool rolls() const { return rolling_on_ || !rolling_rad.empty(); }
    /// Keeps rolling springs from now on (zero for every listed contact) or
    /// drops them: with the rolling law on or off (compute_contact_forces).
    void keep_rolling(bool on)
    {
        rolling_on_ = on;
        rolling_rad.assign(on ? size() : 0, Vec3::Zero());
        rolling_torque_n_m.assign(on ? size() : 0, Vec3::Zero());
    }

    /// Whether a body of `kind` touches wall `wall` this step (false for a
    /// wall added since the last rebuild).
    [[nodiscard]] bool wall_touches(std::size_t wall, BodyKind kind) const;

    /// Replaces the contacts with new ones (sorted by contact_key, pairs then
    /// walls, `walls` walls), keeping the tangential state (and the rolling
    /// springs, where kept) of contacts present in both, and rebuilds the
    /// incidence list.
    void rebuild(std::vector<BodyRef> new_first, std::vector<BodyRef> new_second, std::size_t walls,
        const FlatOffsets& flat);

    /// Puts the contacts, with their memory and outputs, in contact_key
    /// order and indexes them again: for a list sorted by another key (a
    /// snapshot of version 4 or older sorted pairs by (first, second) alone).
    void sort(std::size_t walls, const FlatOffsets& flat);

    /// A wall was added after the others: it has no contacts until the next
    /// rebuild (add_wall calls this, so the list always names the world's walls).
    void append_wall();
    /// Wall `wall` was removed: drops its contacts and renumbers the later
    /// walls', keeping every other contact and its memory (remove_wall).
    void remove_wall(std::size_t wall, const FlatOffsets& flat);

private:
    /// wall_start and the incidence list, from first and second.
    void index(std::size_t walls, const FlatOffsets& flat);
    bool rolling_on_ = false; ///< keep_rolling's choice (what rolls() says of an empty list)
};

/// The listed body pairs that may touch before any body has moved a part of
/// the near skin (a second, shorter Verlet list inside the contact list):
/// those whose gap was below that skin at the selection. The kernel
/// evaluates only these (and every wall contact), and the gather reads only
/// their records. Every other listed pair stays apart until the next
/// selection: its slots are zero (the selection clears a pair that touched
/// last step and is apart now, as the kernel would), and leaving a zero
/// record out of a body's sum changes no bit (gather_forces says why). So
/// which pairs are near, and when they were selected, never shows in a
/// result: a snapshot does not keep them, and a restored run selects afresh.
/// Selected by update_neighbours at every rebuild of the contact list and
/// whenever a body has moved near_reselect_fraction of the near skin since.
struct NearPairs {
    static constexpr std::uint64_t none = ~std::uint64_t{0};
    std::vector<std::uint32_t> pairs;           ///< indices of body pairs in the contact list, ascending
    std::vector<BodyRef> first, second;         ///< their sides (ContactList::first, second), read in a row
    /// Each flat body's incidences (ContactList::incidence, in its order)
    /// on near pairs and on walls: CSR offsets, size bodies + 1.
    std::vector<std::uint32_t> incidence_start;
    std::vector<Incidence> incidence;
    std::vector<Vec3> position_m;               ///< flat positions at the selection

    double skin_m = 0.0;                        ///< the near skin of the selection [m]
    /// The largest move of a body from the contact list's build to the
    /// selection [m]: with the near limit, it bounds a body's move since the
    /// build (update_neighbours).
    double drift_m = 0.0;

    std::uint64_t for_build = none;             ///< the contact list's build (neighbour_builds) it was made from
    std::uint64_t selections = 0;               ///< how many selections so far (a statistic; `all` makes none)
    /// Every listed pair is near, until the next rebuild (the list is rebuilt
    /// too often for selections to pay, update_neighbours): `pairs` is 0, 1,
    /// …, and the list's own sides and incidences serve (`first`, `second`,
    /// `incidence_start`, `incidence` and `position_m` are left empty).
    bool all = false;
    std::uint64_t list_built_at_step = none;    ///< the step count at the contact list's last rebuild

    /// The near pairs' sides (indexed as `pairs`), and each flat body's
    /// incidences on them and on walls: the contact list's own while every
    /// pair is near (then `pairs[k]` is k).
    [[nodiscard]] const std::vector<BodyRef>& first_of(const ContactList& c) const { return all ? c.first : first; }
    [[nodiscard]] const std::vector<BodyRef>& second_of(const ContactList& c) const { return all ? c.second : second; }
    [[nodiscard]] const std::vector<std::uint32_t>& incidence_start_of(const ContactList& c) const
    {
        return all ? c.incidence_start : incidence_start;
    }
    [[nodiscard]] const std::vector<Incidence>& incidence_of(const ContactList& c) const
    {
        return all ? c.incidence : incidence;
    }
};

} // namespace wiredem::engine
