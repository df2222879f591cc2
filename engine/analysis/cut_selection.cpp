// Cut places of lowest strain; see cut_selection.hpp.
#include "analysis/cut_selection.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace wiredem::engine::analysis {

double winding_step_rad(const Vec3& a, const Vec3& b) noexcept
{
    const double ax = a.x(), ay = a.y(), bx = b.x(), by = b.y();
    return std::atan2(ax * by - ay * bx, ax * bx + ay * by);
}

double length_per_loop_m(std::span<const Vec3> node_position_m, double segment_length_m)
{
    if (node_position_m.size() < 2) return 0.0;
    double winding_rad = 0.0;
    for (std::size_t s = 0; s + 1 < node_position_m.size(); ++s)
        winding_rad += winding_step_rad(node_position_m[s], node_position_m[s + 1]);
    const double loops = std::abs(winding_rad) / (2.0 * std::numbers::pi);
    if (!(loops >= 1.0)) return 0.0;
    return static_cast<double>(node_position_m.size() - 1) * segment_length_m / loops;
}

std::vector<CutPlace> lowest_strain_cuts(std::span<const double> segment_strain, double segment_length_m,
    std::size_t count, double min_spacing_m, std::span<const std::uint8_t> excluded)
{
    const std::size_t n = segment_strain.size();
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
        [&](std::uint32_t a, std::uint32_t b) { return segment_strain[a] < segment_strain[b]; });
    std::vector<CutPlace> chosen;
    for (std::uint32_t s : order) {
        if (chosen.size() >= count) break;
        if (s < excluded.size() && excluded[s] != 0) continue;
        if (!std::isfinite(segment_strain[s])) continue;
        // Distances in whole and half segments times l_w: a spacing of k l_w
        // is met by segments k apart, without a rounding of their positions.
        const double at = (static_cast<double>(s) + 0.5) * segment_length_m;
        if (at < min_spacing_m || (static_cast<double>(n - s) - 0.5) * segment_length_m < min_spacing_m) continue;
        const bool apart = std::all_of(chosen.begin(), chosen.end(), [&](const CutPlace& c) {
            const std::uint32_t gap = c.segment > s ? c.segment - s : s - c.segment;
            return static_cast<double>(gap) * segment_length_m >= min_spacing_m;
        });
        if (apart) chosen.push_back({s, at, segment_strain[s]});
    }
    std::sort(chosen.begin(), chosen.end(), [](const CutPlace& a, const CutPlace& b) { return a.segment < b.segment; });
    return chosen;
}

} // namespace wiredem::engine::analysis
