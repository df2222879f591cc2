// Helpers for the integrators: a run of consecutive bodies' vectors seen as
// one flat array of doubles, the runs of bodies of one motion type, and the
// kinematic bodies' move.
//
// Integrating is elementwise: x, y and z of every body get the same update.
// A std::vector<Vec3> stores them contiguously (x₀ y₀ z₀ x₁ y₁ z₁ …), so an
// update written on the flat array of a run of bodies is one loop that the
// compiler vectorises, where the same update body by body splits each Vec3
// into a pair and a single double. The per-element operations, and so the
// results, are the same either way.
#pragma once

#include "core/types.hpp"
#include "state/body_state.hpp"

#include <array>

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
/// whose motion is `which`, in order; the others are skipped.
template <class F>
void for_each_run(const std::vector<Motion>& motion, Motion which, std::size_t begin, std::size_t end, F&& f)
{
    std::size_t b = begin;
    while (b < end) {
        while (b < end && motion[b] != which) ++b;
        std::size_t e = b;
        while (e < end && motion[e] == which) ++e;
        if (e > b) f(b, e);
        b = e;
    }
}

/// δt²/2 · inv_mass · load (F/m, or τ/I) of bodies [b, e), at most
/// integrate_block of them: the scaled acceleration x₂ both integrators set
/// from the forces.
[[nodiscard]] inline std::array<Vec3, integrate_block> scaled_accelerations(std::size_t b, std::size_t e,
    const std::vector<double>& inv_mass, const std::vector<Vec3>& load, double half_dt2)
{
    std::array<Vec3, integrate_block> half_a_dt2;
    for (std::size_t i = b; i < e; ++i) half_a_dt2[i - b] = half_dt2 * inv_mass[i] * load[i];
    return half_a_dt2;
}

/// The kinematic bodies of [begin, end) move by their prescribed x₁ = δt v
/// (their higher derivatives stay zero): x₀ ← x₀ + x₁.
inline void move_kinematic(std::array<std::vector<Vec3>, gear_order>& x, const std::vector<Motion>& motion,
    std::size_t begin, std::size_t end)
{
    for (std::size_t i = begin; i < end; ++i)
        if (motion[i] == Motion::kinematic) x[0][i] += x[1][i];
}

} // namespace wiredem::engine
