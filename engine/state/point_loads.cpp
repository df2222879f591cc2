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
    return loads;
}

void PointLoads::set(BodyRef body, const Vec3& force_n)
{
    if (loads_.empty() || loads_.back().first < body) {
        loads_.emplace_back(body, force_n);
        return;
    }
    const auto at = std::lower_bound(loads_.begin(), loads_.end(), body, before);
    if (at != loads_.end() && at->first == body) at->second = force_n;
    else loads_.emplace(at, body, force_n);
}

std::span<const PointLoads::Load> PointLoads::of(BodyKind kind, std::uint32_t begin, std::uint32_t end) const
{
    const auto first = std::lower_bound(loads_.begin(), loads_.end(), BodyRef(kind, begin), before);
    // From `first` on, the loads of `kind` below `end` come first (the list
    // is sorted): as many as the caller is about to add.
    auto last = first;
    while (last != loads_.end() && last->first.kind() == kind && last->first.index() < end) ++last;
    return {first, last};
}

} // namespace wiredem::engine
