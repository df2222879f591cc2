#include "contact/contact_list.hpp"

#include <algorithm>

namespace wiredem::engine {

std::optional<std::size_t> ContactList::find(BodyRef first_side, BodyRef second_side) const
{
    const std::uint64_t key = contact_key(first_side, second_side);
    std::size_t lo = 0, hi = size();
    while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        const std::uint64_t k = contact_key(first[mid], second[mid]);
        if (k == key) return mid;
        if (k < key)
            lo = mid + 1;
        else
            hi = mid;
    }
    return std::nullopt;
}

bool ContactList::wall_touches(std::size_t wall, BodyKind kind) const
{
    if (wall + 1 >= wall_start.size()) return false;
    for (std::size_t p = wall_start[wall]; p < wall_start[wall + 1]; ++p)
        if (touching[p] && first[p].kind() == kind) return true;
    return false;
}

void ContactList::rebuild(
    std::vector<BodyRef> new_first, std::vector<BodyRef> new_second, std::size_t walls, const FlatOffsets& flat)
{
    const std::size_t n = new_first.size();
    std::vector<TangentialState> carried(n);
    std::vector<std::uint8_t> was_touching(n, 0);
    const bool rolling = rolls();
    std::vector<Vec3> carried_rolling(rolling ? n : 0, Vec3::Zero());
    // Merge of two sorted key lists: springs follow their contact.
    for (std::size_t i = 0, j = 0; i < n && j < size();) {
        const std::uint64_t new_key = contact_key(new_first[i], new_second[i]);
        const std::uint64_t old_key = contact_key(first[j], second[j]);
        if (new_key < old_key) {
            ++i;
        } else if (old_key < new_key) {
            ++j;
        } else {
            carried[i] = tangential[j];
            was_touching[i] = touching[j];
            if (rolling) carried_rolling[i] = rolling_rad[j];
            ++i;
            ++j;
        }
    }
    first = std::move(new_first);
    second = std::move(new_second);
    tangential = std::move(carried);
    touching = std::move(was_touching);
    output.assign(n, ContactOutput{});
    if (rolling) {
        rolling_rad = std::move(carried_rolling);
        rolling_torque_n_m.assign(n, Vec3::Zero());
    }
    index(walls, flat);
}

void ContactList::sort(std::size_t walls, const FlatOffsets& flat)
{
    std::vector<std::uint32_t> order(size());
    for (std::uint32_t p = 0; p < order.size(); ++p) order[p] = p;
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return contact_key(first[a], second[a]) < contact_key(first[b], second[b]);
    });
    const auto permute = [&](auto& v) {
        if (v.size() != order.size()) return; // not computed yet (hertz_coefficient before a rebuild)
        auto sorted = v;
        for (std::size_t p = 0; p < order.size(); ++p) sorted[p] = v[order[p]];
        v = std::move(sorted);
    };
    permute(first);
    permute(second);
    permute(hertz_coefficient);
    permute(tangential);
    permute(output);
    permute(touching);
    permute(rolling_rad);
    permute(rolling_torque_n_m);
    index(walls, flat);
}

void ContactList::append_wall()
{
    if (!wall_start.empty()) wall_start.push_back(static_cast<std::uint32_t>(size()));
}

void ContactList::remove_wall(std::size_t wall, const FlatOffsets& flat)
{
    if (wall + 1 >= wall_start.size()) return; // not listed yet
    const auto begin = static_cast<std::ptrdiff_t>(wall_start[wall]), end = static_cast<std::ptrdiff_t>(wall_start[wall + 1]);
    auto cut = [&](auto& v) {
        if (!v.empty()) v.erase(v.begin() + begin, v.begin() + end); // the rolling springs only while kept
    };
    cut(first);
    cut(second);
    cut(hertz_coefficient);
    cut(tangential);
    cut(output);
    cut(touching);
    cut(rolling_rad);
    cut(rolling_torque_n_m);
    for (std::size_t p = static_cast<std::size_t>(begin); p < size(); ++p) second[p] = wall_ref(second[p].index() - 1);
    index(wall_start.size() - 2, flat);
}

void ContactList::index(std::size_t walls, const FlatOffsets& flat)
{
    const std::size_t n = size();
    // Pairs first, then each wall's contacts, by wall.
    const auto pairs = std::find_if(second.begin(), second.end(), [](BodyRef b) { return is_wall(b); }) - second.begin();
    wall_start.assign(walls + 1, 0);
    wall_start[0] = static_cast<std::uint32_t>(pairs);
    for (std::size_t p = static_cast<std::size_t>(pairs); p < n; ++p) ++wall_start[second[p].index() + 1];
    for (std::size_t i = 0; i < walls; ++i) wall_start[i + 1] += wall_start[i];

    auto flat_of = [&](BodyRef b) { return flat[static_cast<int>(b.kind())] + b.index(); };
    const std::uint32_t bodies = flat[body_kind_count];
    incidence_start.assign(bodies + 1, 0);
    for (std::size_t p = 0; p < n; ++p) {
        ++incidence_start[flat_of(first[p]) + 1];
        if (!is_wall(second[p])) ++incidence_start[flat_of(second[p]) + 1];
    }
    for (std::size_t b = 0; b < bodies; ++b) incidence_start[b + 1] += incidence_start[b];
    incidence.resize(incidence_start[bodies]);
    std::vector<std::uint32_t> fill(incidence_start.begin(), incidence_start.end() - 1);
    for (std::size_t p = 0; p < n; ++p) { // ascending p: each body's list is in contact order
        incidence[fill[flat_of(first[p])]++] = {static_cast<std::uint32_t>(p), true};
        if (!is_wall(second[p])) incidence[fill[flat_of(second[p])]++] = {static_cast<std::uint32_t>(p), false};
    }
}

} // namespace wiredem::engine
