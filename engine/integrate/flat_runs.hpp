// Helpers for the integrators: a run of consecutive bodies' vectors seen as
// one flat array of doubles, and the runs of bodies that move.
//
// Integrating is elementwise: x, y and z of every body get the same update.
// A std::vector<Vec3> stores them contiguously (x₀ y₀ z₀ x₁ y₁ z₁ …), so an
// update written on the flat array of a run of bodies is one loop that the
// compiler vectorises, where the same update body by body splits each Vec3
// into a pair and a single double. The per-element operations, and so the
// results, are the same either way.
#pragma once

#include "core/types.hpp"

#include <cstddef>
#include <vector>

namespace wiredem::engine {

/// Bodies per block of the integrators' parallel loops: a block's six
/// derivative arrays (6 × 3 KB) and scratch stay in L1.
inline constexpr std::size_t integrate_block = 128;

static_assert(sizeof(Vec3) == 3 * sizeof(double), "flat() needs Vec3 to be three packed doubles");

/// Components of bodies [begin, end) of `v` as one flat array of 3 (end − begin) doubles.
[[nodiscard]] inline Eigen::Map<Eigen::ArrayXd> flat(std::vector<Vec3>& v, std::size_t begin, std::size_t end)
{
    return {v.data()->data() + 3 * begin, static_cast<Eigen::Index>(3 * (end - begin))};
}

/// Calls f(b, e) for each maximal run [b, e) within [begin, end) of bodies
/// that move (inv_mass_per_kg ≠ 0), in order; bodies held fixed are skipped.
template <class F>
void for_each_moving_run(const std::vector<double>& inv_mass_per_kg, std::size_t begin, std::size_t end, F&& f)
{
    std::size_t b = begin;
    while (b < end) {
        while (b < end && inv_mass_per_kg[b] == 0.0) ++b;
        std::size_t e = b;
        while (e < end && inv_mass_per_kg[e] != 0.0) ++e;
        if (e > b) f(b, e);
        b = e;
    }
}

} // namespace wiredem::engine
