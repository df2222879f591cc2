#include "broadphase/cell_grid.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace wiredem::engine {

std::vector<std::pair<std::uint32_t, std::uint32_t>> CellGrid::find_pairs(ThreadPool& pool,
    const std::vector<Vec3>& pos, const std::vector<double>& radius, double skin_m, const PartnerRanges& partners,
    const PairFilter& filter)
{
    using Pair = std::pair<std::uint32_t, std::uint32_t>;
    const std::size_t n = pos.size();
    if (n < 2) return {};

    Vec3 lo = pos[0], hi = pos[0];
    double r_max = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        lo = lo.cwiseMin(pos[i]);
        hi = hi.cwiseMax(pos[i]);
        r_max = std::max(r_max, radius[i]);
    }
    // A body that has flown off to infinity (a blown-up run, flagged by the
    // step) must not make the grid unbounded: clamp the box to finite values.
    if (!lo.allFinite() || !hi.allFinite()) {
        lo = lo.cwiseMax(Vec3::Constant(-1e6)).cwiseMin(Vec3::Constant(1e6));
        hi = hi.cwiseMax(Vec3::Constant(-1e6)).cwiseMin(Vec3::Constant(1e6));
        for (int d = 0; d < 3; ++d) {
            if (std::isnan(lo[d])) lo[d] = -1e6;
            if (std::isnan(hi[d])) hi[d] = 1e6;
        }
    }
    // Cells at least one interaction range wide; coarsen if the box is so
    // sparse that the grid would hold far more cells than bodies.
    double cell = 2.0 * r_max + skin_m;
    std::array<std::int64_t, 3> dims{};
    const double max_cells = static_cast<double>(8 * n + 64);
    for (;;) {
        double total = 1.0;
        for (int d = 0; d < 3; ++d) total *= std::floor((hi[d] - lo[d]) / cell) + 1.0;
        if (total <= max_cells) break;
        cell *= 1.5;
    }
    for (int d = 0; d < 3; ++d) dims[d] = static_cast<std::int64_t>(std::floor((hi[d] - lo[d]) / cell)) + 1;
    const std::size_t cells = static_cast<std::size_t>(dims[0] * dims[1] * dims[2]);
    auto coord = [&](const Vec3& p, int d) {
        const double c = std::clamp((p[d] - lo[d]) / cell, 0.0, static_cast<double>(dims[d] - 1));
        return std::isnan(c) ? std::int64_t{0} : static_cast<std::int64_t>(c);
    };

    // Counting sort of bodies by cell: ids ascend within each cell.
    body_cell_.resize(n);
    cell_start_.assign(cells + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const auto c = static_cast<std::uint32_t>((coord(pos[i], 2) * dims[1] + coord(pos[i], 1)) * dims[0] + coord(pos[i], 0));
        body_cell_[i] = c;
        ++cell_start_[c + 1];
    }
    for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
    cell_bodies_.resize(n);
    {
        std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
        for (std::size_t i = 0; i < n; ++i) cell_bodies_[fill[body_cell_[i]]++] = static_cast<std::uint32_t>(i);
    }

    constexpr std::size_t chunk = 512;
    const std::size_t chunks = (n + chunk - 1) / chunk;
    std::vector<std::vector<Pair>> found(chunks);
    parallel_for(
        pool, chunks,
        [&](std::size_t ch) {
            std::vector<Pair>& out = found[ch];
            std::vector<std::uint32_t> found_j;
            const std::size_t end = std::min(n, (ch + 1) * chunk);
            std::size_t group = 0;
            for (std::size_t i = ch * chunk; i < end; ++i) {
                while (group + 2 < partners.group_start.size() && i >= partners.group_start[group + 1]) ++group;
                const auto& ranges = partners.partner_ranges[group];
                found_j.clear();
                const std::int64_t cx = coord(pos[i], 0), cy = coord(pos[i], 1), cz = coord(pos[i], 2);
                for (std::int64_t z = std::max<std::int64_t>(cz - 1, 0); z <= std::min(cz + 1, dims[2] - 1); ++z)
                    for (std::int64_t y = std::max<std::int64_t>(cy - 1, 0); y <= std::min(cy + 1, dims[1] - 1); ++y)
                        for (std::int64_t x = std::max<std::int64_t>(cx - 1, 0); x <= std::min(cx + 1, dims[0] - 1); ++x) {
                            const std::size_t c = static_cast<std::size_t>((z * dims[1] + y) * dims[0] + x);
                            const std::uint32_t* cell_begin = cell_bodies_.data() + cell_start_[c];
                            const std::uint32_t* cell_end = cell_bodies_.data() + cell_start_[c + 1];
                            // A cell's bodies ascend: each range of partners
                            // j > i is a run found by bisection.
                            for (const auto& [lo, hi] : ranges) {
                                const auto first = std::max<std::size_t>(lo, i + 1);
                                for (const std::uint32_t* k = std::lower_bound(cell_begin, cell_end, first);
                                     k != cell_end && *k < hi; ++k) {
                                    const std::uint32_t j = *k;
                                    const double reach = radius[i] + radius[j] + skin_m;
                                    if ((pos[i] - pos[j]).squaredNorm() >= reach * reach) continue;
                                    if (filter && !filter(static_cast<std::uint32_t>(i), j)) continue;
                                    found_j.push_back(j);
                                }
                            }
                        }
                std::sort(found_j.begin(), found_j.end());
                for (std::uint32_t j : found_j) out.emplace_back(static_cast<std::uint32_t>(i), j);
            }
        },
        1);

    std::size_t total = 0;
    for (const auto& f : found) total += f.size();
    std::vector<Pair> pairs;
    pairs.reserve(total);
    for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
    return pairs;
}

} // namespace wiredem::engine
