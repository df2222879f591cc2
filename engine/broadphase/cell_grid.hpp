// Candidate-pair search on a uniform cell grid (the neighbour list with a
// Verlet skin is built from it; see contact/contact_list.hpp).
//
// Bodies are binned by a counting sort, which also copies each body's
// position and radius into its slot: the three cells of a row along x are
// consecutive, so the 27 surrounding cells of a body are nine streams of
// slots. For every body i those are scanned for partners j > i within
// r_i + r_j + skin, eight (AVX-512) or four (AVX2) slots per instruction
// (cell_grid_lanes.inc; the scalar path tests the same way, so every path
// finds the same pairs); a body whose group has no later partner (the
// membrane) scans nothing. Each fixed-size chunk of i writes its own list and the lists
// are concatenated in chunk order, so the result is sorted by (i, j) and
// identical for any thread count. O(N) for bounded density.
#pragma once

#include "core/types.hpp"
#include "parallel/thread_pool.hpp"

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace wiredem::engine {

/// Decides whether two bodies (flat indices, i < j) may interact at all.
using PairFilter = std::function<bool(std::uint32_t, std::uint32_t)>;

/// Where a body's partners may be, by groups of consecutive indices (the
/// body kinds): group g is the bodies [group_start[g], group_start[g + 1]),
/// and a body of group g pairs only with indices in partner_ranges[g]
/// ([begin, end) each, ascending). The search never looks at the others:
/// membrane nodes, the last and largest group, pair with no later body.
struct PartnerRanges {
    std::vector<std::uint32_t> group_start;
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> partner_ranges;
};

/// The bodies in cell order (a cell's slots ascend by body id), as arrays of
/// components, so that the candidates of a row of cells are read as streams,
/// several slots per instruction. Padded past the last slot (id +∞).
struct GridSlots {
    std::vector<double> x, y, z, r; ///< position and radius [m]
    std::vector<double> id;         ///< the body's flat index, as a double (exact)
    std::vector<std::uint32_t> body; ///< the body's flat index
};

/// Uniform grid over the bounding box of the bodies.
class CellGrid {
public:
    /// Finds all pairs (i < j) with |x_i − x_j| < r_i + r_j + skin_m, j in
    /// the partner ranges of i's group, that pass `filter`, sorted by (i, j).
    /// Cells are at least 2 max(r) + skin wide.
    [[nodiscard]] std::vector<std::pair<std::uint32_t, std::uint32_t>> find_pairs(ThreadPool& pool,
        const std::vector<Vec3>& position_m, const std::vector<double>& radius_m, double skin_m,
        const PartnerRanges& partners, const PairFilter& filter);

    /// Number of cells of the last build (for diagnostics).
    [[nodiscard]] std::size_t cell_count() const { return cell_start_.empty() ? 0 : cell_start_.size() - 1; }

private:
    std::vector<std::uint32_t> cell_start_;   ///< CSR offsets, size cells + 1
    std::vector<std::uint32_t> body_cell_;
    GridSlots slots_;
};

} // namespace wiredem::engine
