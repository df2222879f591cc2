#include "broadphase/cell_grid.hpp"

#include "contact/pair_kernel_simd.hpp"

#if defined(__x86_64__)
#include "contact/avx2.hpp"
#include "contact/avx512.hpp"
#endif

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>

namespace wiredem::engine {
namespace {

/// Padding past the last slot: the widest SIMD path's lanes.
constexpr std::size_t slot_padding = 8;

/// What a slot must pass to be a candidate of body i at (x, y, z): its id
/// in [first, hi), and (dx² + dy²) + dz² < ((r_i + r_j) + skin)².
struct CandidateTest {
    double x, y, z, radius_m, skin_m;
    double first, hi;
};

/// The candidate test one slot at a time; the SIMD paths' operations, lane by lane.
std::size_t near_scalar(const GridSlots& slots, std::size_t begin, std::size_t end, const CandidateTest& at,
    std::uint32_t* out)
{
    std::size_t found = 0;
    for (std::size_t s = begin; s < end; ++s) {
        const double dx = at.x - slots.x[s], dy = at.y - slots.y[s], dz = at.z - slots.z[s];
        const double reach = (at.radius_m + slots.r[s]) + at.skin_m;
        const bool near = (dx * dx + dy * dy) + dz * dz < reach * reach;
        if (near && slots.id[s] >= at.first && slots.id[s] < at.hi) out[found++] = slots.body[s];
    }
    return found;
}

#if defined(__x86_64__)
#define WIREDEM_LANES_KERNELS "broadphase/cell_grid_lanes.inc"
#include "contact/lanes_for_each_isa.inc"
#endif

using NearRun = std::size_t (*)(const GridSlots&, std::size_t, std::size_t, const CandidateTest&, std::uint32_t*);

/// The candidate test of the instruction set in use (all give the same candidates).
NearRun near_run_for_isa()
{
    WIREDEM_WITH_SIMD_ISA(isa, return &isa::near_run);
    return &near_scalar;
}

} // namespace

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
    GridSlots& slots = slots_;
    for (auto* v : {&slots.x, &slots.y, &slots.z, &slots.r}) v->assign(n + slot_padding, 0.0);
    slots.id.assign(n + slot_padding, std::numeric_limits<double>::infinity()); // never in a range
    slots.body.assign(n + slot_padding, 0);
    {
        std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint32_t s = fill[body_cell_[i]]++;
            slots.x[s] = pos[i].x(), slots.y[s] = pos[i].y(), slots.z[s] = pos[i].z(), slots.r[s] = radius[i];
            slots.id[s] = static_cast<double>(i);
            slots.body[s] = static_cast<std::uint32_t>(i);
        }
    }
    const NearRun near_run = near_run_for_isa();
    // Each group's partner ranges with the adjacent ones merged: with every
    // kind touching, one range.
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> ranges_of(partners.partner_ranges.size());
    for (std::size_t g = 0; g < ranges_of.size(); ++g)
        for (const auto& [lo_j, hi_j] : partners.partner_ranges[g]) {
            if (lo_j >= hi_j) continue;
            if (!ranges_of[g].empty() && ranges_of[g].back().second == lo_j) ranges_of[g].back().second = hi_j;
            else ranges_of[g].emplace_back(lo_j, hi_j);
        }

    constexpr std::size_t chunk = 512;
    const std::size_t chunks = (n + chunk - 1) / chunk;
    std::vector<std::vector<Pair>> found(chunks);
    parallel_for(
        pool, chunks,
        [&](std::size_t ch) {
            std::vector<Pair>& out = found[ch];
            std::vector<std::uint32_t> found_j;
            std::vector<std::uint32_t> near; // a run's candidates
            const std::size_t end = std::min(n, (ch + 1) * chunk);
            std::size_t group = 0;
            for (std::size_t i = ch * chunk; i < end; ++i) {
                while (group + 2 < partners.group_start.size() && i >= partners.group_start[group + 1]) ++group;
                const auto& ranges = ranges_of[group];
                if (ranges.empty() || ranges.back().second <= i + 1) continue; // no later partner
                found_j.clear();
                const Vec3 p = pos[i];
                CandidateTest at{p.x(), p.y(), p.z(), radius[i], skin_m, 0.0, 0.0};
                const std::int64_t cx = coord(p, 0), cy = coord(p, 1), cz = coord(p, 2);
                const std::int64_t x0 = std::max<std::int64_t>(cx - 1, 0), x1 = std::min(cx + 1, dims[0] - 1);
                for (std::int64_t z = std::max<std::int64_t>(cz - 1, 0); z <= std::min(cz + 1, dims[2] - 1); ++z)
                    for (std::int64_t y = std::max<std::int64_t>(cy - 1, 0); y <= std::min(cy + 1, dims[1] - 1); ++y) {
                        // The row's three cells are consecutive, and so are their slots.
                        const std::size_t row = static_cast<std::size_t>((z * dims[1] + y) * dims[0]);
                        const std::uint32_t s_begin = cell_start_[row + static_cast<std::size_t>(x0)];
                        const std::uint32_t s_end = cell_start_[row + static_cast<std::size_t>(x1) + 1];
                        if (near.size() < s_end - s_begin) near.resize(s_end - s_begin);
                        for (const auto& [lo_j, hi_j] : ranges) {
                            at.first = static_cast<double>(std::max<std::size_t>(lo_j, i + 1));
                            at.hi = static_cast<double>(hi_j);
                            const std::size_t count = near_run(slots, s_begin, s_end, at, near.data());
                            for (std::size_t k = 0; k < count; ++k)
                                if (!filter || filter(static_cast<std::uint32_t>(i), near[k]))
                                    found_j.push_back(near[k]);
                        }
                    }
                std::sort(found_j.begin(), found_j.end());
                for (std::uint32_t j : found_j) out.emplace_back(static_cast<std::uint32_t>(i), j);
            }
        },
        1);

    // The chunks' pairs one after the other, each chunk copied by a thread.
    std::vector<std::size_t> start(chunks + 1, 0);
    for (std::size_t ch = 0; ch < chunks; ++ch) start[ch + 1] = start[ch] + found[ch].size();
    std::vector<Pair> pairs(start[chunks]);
    parallel_for(
        pool, chunks, [&](std::size_t ch) { std::copy(found[ch].begin(), found[ch].end(), pairs.begin() + static_cast<std::ptrdiff_t>(start[ch])); },
        1);
    return pairs;
}

} // namespace wiredem::engine
