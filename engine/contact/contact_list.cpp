#include "contact/contact_list.hpp"

namespace wiredem::engine {

void ContactList::rebuild(const std::vector<std::uint64_t>& new_keys, const std::vector<BodyRef>& new_first,
    const std::vector<BodyRef>& new_second, const std::vector<std::uint32_t>& new_flat_first,
    const std::vector<std::uint32_t>& new_flat_second, std::size_t flat_body_count)
{
    const std::size_t n = new_keys.size();
    std::vector<TangentialState> carried(n);
    std::vector<std::uint8_t> was_touching(n, 0);
    // Merge of two sorted key lists: springs follow their pair.
    for (std::size_t i = 0, j = 0; i < n && j < key.size();) {
        if (new_keys[i] < key[j]) {
            ++i;
        } else if (key[j] < new_keys[i]) {
            ++j;
        } else {
            carried[i] = tangential[j];
            was_touching[i] = touching[j];
            ++i;
            ++j;
        }
    }
    key = new_keys;
    first = new_first;
    second = new_second;
    flat_first = new_flat_first;
    flat_second = new_flat_second;
    tangential = std::move(carried);
    touching = std::move(was_touching);
    force_n.assign(n, Vec3::Zero());
    normal_force_n.assign(n, 0.0);

    incidence_start.assign(flat_body_count + 1, 0);
    for (std::size_t p = 0; p < n; ++p) {
        ++incidence_start[flat_first[p] + 1];
        ++incidence_start[flat_second[p] + 1];
    }
    for (std::size_t b = 0; b < flat_body_count; ++b) incidence_start[b + 1] += incidence_start[b];
    incidence.resize(2 * n);
    share_of_first.resize(n);
    share_of_second.resize(n);
    std::vector<std::uint32_t> fill(incidence_start.begin(), incidence_start.end() - 1);
    for (std::size_t p = 0; p < n; ++p) { // ascending p: each body's list is in pair order
        share_of_first[p] = fill[flat_first[p]]++;
        share_of_second[p] = fill[flat_second[p]]++;
        incidence[share_of_first[p]] = {static_cast<std::uint32_t>(p), true};
        incidence[share_of_second[p]] = {static_cast<std::uint32_t>(p), false};
    }
    shares.assign(2 * n, ContactShare{});
}

} // namespace wiredem::engine
