#include "state/point_loads.hpp"

#include <algorithm>
#include <array>

namespace wiredem::engine {

namespace {

/// "wire node 3", for the messages.
std::string body_text(BodyRef b)
{
    static constexpr std::array<const char*, body_kind_count> kinds{"grain ", "wire node ", "membrane node "};
    if (is_wall(b)) return "wall " + std::to_string(b.index());
    return kinds[static_cast<std::size_t>(b.kind())] + std::to_string(b.index());
}

/// Orders a load against a body.
bool before(const PointLoads::Load& l, BodyRef b) { return l.first < b; }

} // namespace

Result<PointLoads, std::string> PointLoads::from_sorted(std::vector<Load> list)
{
    for (std::size_t i = 1; i < list.size(); ++i)
        if (!(list[i - 1].first < list[i].first))
            return Err("entry " + std::to_string(i) + " (" + body_text(list[i].first) + ") "
                       + (list[i - 1].first == list[i].first ? "names the body of" : "comes before")
                       + " entry " + std::to_string(i - 1) + " (" + body_text(list[i - 1].first)
                       + "): the loads must be sorted by body (grains, wire nodes, membrane nodes, each by index),"
                         " each body at most once");
    PointLoads loads;
    loads.loads_ = std::move(list);
    loads.index_kinds();
    return loads;
}

void PointLoads::set(BodyRef body, const Vec3& force_n)
{
    if (loads_.empty() || loads_.back().first < body) {
        loads_.emplace_back(body, force_n);
    } else {
        const auto at = std::lower_bound(loads_.begin(), loads_.end(), body, before);
        if (at != loads_.end() && at->first == body) at->second = force_n;
        else loads_.emplace(at, body, force_n);
    }
    index_kinds();
}

void PointLoads::index_kinds() noexcept
{
    // Walls (kind bits 3) sort after every body: past the last kind's end.
    for (int k = 0; k < body_kind_count; ++k)
        kind_start_[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(
            std::lower_bound(loads_.begin(), loads_.end(), BodyRef(static_cast<BodyKind>(k), 0), before) - loads_.begin());
    kind_start_[body_kind_count] = static_cast<std::uint32_t>(
        std::partition_point(loads_.begin(), loads_.end(), [](const Load& l) { return !is_wall(l.first); }) - loads_.begin());
}

std::span<const PointLoads::Load> PointLoads::of(BodyKind kind, std::uint32_t begin, std::uint32_t end) const
{
    const auto k = static_cast<std::size_t>(kind);
    const auto first = loads_.begin() + kind_start_[k], last = loads_.begin() + kind_start_[k + 1];
    if (first == last || begin >= end) return {};
    // The kind's loads name bodies lo, lo + 1, …, lo + count − 1: found by index.
    const std::uint32_t lo = first->first.index(), count = kind_start_[k + 1] - kind_start_[k];
    if ((last - 1)->first.index() - lo + 1 == count) {
        const auto at = [&](std::uint32_t i) { return i <= lo ? 0u : std::min(i - lo, count); };
        return {first + at(begin), first + at(end)};
    }
    const auto from = std::lower_bound(first, last, BodyRef(kind, begin), before);
    auto to = from; // the loads the caller is about to add
    while (to != last && to->first.index() < end) ++to;
    return {from, to};
}

} // namespace wiredem::engine
