// The cell grid's candidate pairs (broadphase/cell_grid.hpp) against a search
// over every pair: the same pairs in the same order, on every SIMD path and
// the scalar one, for 1 and 3 threads. Bodies of three radii in three groups
// (as the kinds are), clustered so that cells hold from none to dozens, one
// pair at the reach (the test is strict: |x_i − x_j| < reach is a pair).
#include "broadphase/cell_grid.hpp"
#include "contact/pair_kernel_simd.hpp"
#include "helpers.hpp"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

using namespace wiredem::engine;

namespace {

using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

/// Every pair (i < j) within reach whose j is in i's group's partner ranges
/// and that `filter` keeps, sorted by (i, j): the definition find_pairs meets.
Pairs all_pairs(const std::vector<Vec3>& pos, const std::vector<double>& radius, double skin,
    const PartnerRanges& partners, const PairFilter& filter)
{
    Pairs pairs;
    std::size_t group = 0;
    for (std::uint32_t i = 0; i < pos.size(); ++i) {
        while (group + 2 < partners.group_start.size() && i >= partners.group_start[group + 1]) ++group;
        for (std::uint32_t j = i + 1; j < pos.size(); ++j) {
            bool partner = false;
            for (const auto& [lo, hi] : partners.partner_ranges[group]) partner = partner || (j >= lo && j < hi);
            const double dx = pos[i].x() - pos[j].x(), dy = pos[i].y() - pos[j].y(), dz = pos[i].z() - pos[j].z();
            const double reach = (radius[i] + radius[j]) + skin;
            if (partner && (dx * dx + dy * dy) + dz * dz < reach * reach && (!filter || filter(i, j)))
                pairs.emplace_back(i, j);
        }
    }
    return pairs;
}

} // namespace

TEST(CellGrid, FindsExactlyThePairsASearchOverAllPairsFinds)
{
    // Groups: 600 large bodies, 300 small ones, 500 tiny ones; the large pair
    // with the large and the tiny (two ranges with a gap), the small with the
    // small only (a range ending before the last body), the tiny with nothing later.
    const std::uint32_t large = 600, small = 300, tiny = 500;
    PartnerRanges partners;
    partners.group_start = {0, large, large + small, large + small + tiny};
    partners.partner_ranges = {{{0, large}, {large + small, large + small + tiny}}, {{large, large + small}}, {}};
    std::vector<Vec3> pos;
    std::vector<double> radius;
    std::uint64_t state = 5;
    auto uniform = [&] { // [0, 1)
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) * 0x1p-53;
    };
    for (std::uint32_t i = 0; i < large + small + tiny; ++i) {
        const double r = i < large ? 1e-3 : i < large + small ? 0.3e-3 : 0.1e-3;
        // Half in a dense ball, half spread out, so that cells hold from none to dozens.
        const double spread = i % 2 == 0 ? 4e-3 : 20e-3;
        const double z = uniform(), y = uniform(), x = uniform();
        pos.emplace_back(spread * x, spread * y, spread * z);
        radius.push_back(r);
    }
    const double skin = 0.2e-3;
    // A pair at the reach (to the rounding of the sum): on the boundary of the strict test.
    pos[10] = Vec3(0.05, 0.05, 0.05);
    pos[11] = pos[10] + Vec3((radius[10] + radius[11]) + skin, 0.0, 0.0);
    const PairFilter odd_sum = [](std::uint32_t i, std::uint32_t j) { return (i + j) % 7 != 0; };
    const test::RestoreSimdKernels restore;
    for (const PairFilter& filter : {PairFilter{}, odd_sum}) {
        const Pairs expected = all_pairs(pos, radius, skin, partners, filter);
        ASSERT_GT(expected.size(), 1000u);
        std::vector<SimdKernels> paths = test::simd_choices();
        paths.push_back(SimdKernels::scalar);
        for (const SimdKernels path : paths)
            for (const unsigned threads : {1u, 3u}) {
                set_simd_kernels(path);
                ThreadPool pool(threads);
                CellGrid grid;
                EXPECT_EQ(grid.find_pairs(pool, pos, radius, skin, partners, filter), expected)
                    << "path " << static_cast<int>(path) << ", " << threads << " threads";
            }
    }
}
