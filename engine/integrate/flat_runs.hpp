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

#include "core/assert.hpp"
#include "core/types.hpp"
#include "parallel/body_blocks.hpp"
#include "state/body_state.hpp"
#include "state/world.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace wiredem::engine {

/// Bodies the integrators' loops take at a time within a block of their
/// parallel loops (body_block, parallel/body_blocks.hpp): six derivative
/// arrays (6 × 3 KB) and scratch stay in L1.
inline constexpr std::size_t integrate_block = 128;

static_assert(sizeof(Vec3) == 3 * sizeof(double), "flat() needs Vec3 to be three packed doubles");

/// Components of bodies [begin, end) of `v` as one flat array of 3 (end − begin) doubles.
[[nodiscard]] inline Eigen::Map<Eigen::ArrayXd> flat(std::vector<Vec3>& v, std::size_t begin, std::size_t end)
{
    return {v.data()->data() + 3 * begin, static_cast<Eigen::Index>(3 * (end - begin))};
}

/// 1 if v is not finite (±∞ or NaN: its exponent bits all set), else 0. An
/// or-reduction of it has no branch and no floating-point order, so loops
/// that fold it in still vectorise.
[[nodiscard]] inline std::uint64_t non_finite_bit(double v)
{
    constexpr std::uint64_t exponent = 0x7ff0000000000000ull;
    return static_cast<std::uint64_t>((std::bit_cast<std::uint64_t>(v) & exponent) == exponent);
}

/// Whether the n doubles at v are all finite (neither ±∞ nor NaN). A
/// branch-free loop built for AVX2 where the SIMD paths run (flat_runs.cpp):
/// Eigen's allFinite stops at the first non-finite value, so it checks one
/// double at a time, ~6 % of a Gear-5 step of the paper-size cell.
[[nodiscard]] bool all_finite(const double* v, std::size_t n);

/// Whether bodies [b, e) of `v` have finite components only.
[[nodiscard]] inline bool all_finite(const std::vector<Vec3>& v, std::size_t b, std::size_t e)
{
    return all_finite(v.data()->data() + 3 * b, 3 * (e - b));
}

/// Eight motions read as one word (Motion is one byte).
[[nodiscard]] inline std::uint64_t motion_word(const Motion* m)
{
    std::uint64_t word;
    std::memcpy(&word, m, sizeof word);
    return word;
}

/// `which` in each of a word's eight bytes.
[[nodiscard]] inline std::uint64_t motion_pattern(Motion which)
{
    return 0x0101010101010101ull * static_cast<std::uint8_t>(which);
}

/// Whether motion[b, e) are all `which`. Eight bodies per comparison of
/// words: the compiler left a loop byte by byte unvectorised (a compare and
/// an or per body, ~3 % of a Gear-5 step of the paper-size cell).
[[nodiscard]] inline bool all_of_motion(const std::vector<Motion>& motion, Motion which, std::size_t b, std::size_t e)
{
    const std::uint64_t pattern = motion_pattern(which);
    std::uint64_t other = 0;
    std::size_t i = b;
    for (; i + 8 <= e; i += 8) other |= motion_word(&motion[i]) ^ pattern;
    for (; i < e; ++i) other |= static_cast<std::uint64_t>(motion[i] != which);
    return other == 0;
}

/// Non-zero exactly when one of the eight motions in `word` is `which`. A word
/// w = motions ^ pattern has a zero byte exactly where a body's motion is
/// `which`; (w − 0x01…01) & ~w & 0x80…80 is non-zero exactly when w has one.
[[nodiscard]] inline std::uint64_t word_has_motion(std::uint64_t word, Motion which)
{
    constexpr std::uint64_t ones = 0x0101010101010101ull, highs = 0x8080808080808080ull;
    const std::uint64_t w = word ^ motion_pattern(which);
    return (w - ones) & ~w & highs;
}

/// Whether any of motion[b, e) is `which` (all_of_motion's twin), eight per word.
[[nodiscard]] inline bool any_of_motion(const std::vector<Motion>& motion, Motion which, std::size_t b, std::size_t e)
{
    std::uint64_t found = 0;
    std::size_t i = b;
    for (; i + 8 <= e; i += 8) found |= word_has_motion(motion_word(&motion[i]), which);
    for (; i < e; ++i) found |= static_cast<std::uint64_t>(motion[i] == which);
    return found != 0;
}

/// Whether a body of this motion is moved by prescription (kinematic or fixed)
/// rather than from its forces (dynamic) or with its clump (clumped).
[[nodiscard]] inline bool is_prescribed(Motion m)
{
    return m == Motion::kinematic || m == Motion::fixed;
}

/// Whether any of motion[b, e) is prescribed (is_prescribed): one pass, eight
/// per word and without a branch, as cheap as all_of_motion on a block of
/// dynamic bodies (the usual one).
[[nodiscard]] inline bool any_prescribed(const std::vector<Motion>& motion, std::size_t b, std::size_t e)
{
    std::uint64_t found = 0;
    std::size_t i = b;
    for (; i + 8 <= e; i += 8) {
        const std::uint64_t word = motion_word(&motion[i]);
        found |= word_has_motion(word, Motion::kinematic) | word_has_motion(word, Motion::fixed);
    }
    for (; i < e; ++i) found |= static_cast<std::uint64_t>(is_prescribed(motion[i]));
    return found != 0;
}

/// Calls f(b, e) for each maximal run [b, e) within [begin, end) of bodies
/// whose motion is `which`, in order; the others are skipped.
template <class F>
void for_each_run(const std::vector<Motion>& motion, Motion which, std::size_t begin, std::size_t end, F&& f)
{
    if (begin < end && all_of_motion(motion, which, begin, end)) { // the usual block: one run
        f(begin, end);
        return;
    }
    std::size_t b = begin;
    while (b < end) {
        while (b < end && motion[b] != which) ++b;
        std::size_t e = b;
        while (e < end && motion[e] == which) ++e;
        if (e > b) f(b, e);
        b = e;
    }
}

/// out[i − b] = δt²/2 · inv_mass[i] · load[i] (F/m, or τ/I) for bodies [b, e),
/// e − b ≤ integrate_block: the scaled acceleration x₂ both integrators set
/// from the forces. Built for AVX2 where the SIMD paths run (flat_runs.cpp).
void scale_accelerations(const double* inv_mass, const Vec3* load, double half_dt2, std::size_t n, Vec3* out);

/// scale_accelerations of bodies [b, e) into a block's scratch.
[[nodiscard]] inline std::array<Vec3, integrate_block> scaled_accelerations(std::size_t b, std::size_t e,
    const std::vector<double>& inv_mass, const std::vector<Vec3>& load, double half_dt2)
{
    std::array<Vec3, integrate_block> half_a_dt2;
    scale_accelerations(inv_mass.data() + b, load.data() + b, half_dt2, e - b, half_a_dt2.data());
    return half_a_dt2;
}

/// A kinematic body moves by its prescribed x₁ = δt v (its higher
/// derivatives stay zero): x₀ ← x₀ + x₁.
inline void move_kinematic_body(std::array<std::vector<Vec3>, gear_order>& x, std::size_t i)
{
    x[0][i] += x[1][i];
}

/// The kinematic bodies of [begin, end) move (move_kinematic_body).
inline void move_kinematic(std::array<std::vector<Vec3>, gear_order>& x, const std::vector<Motion>& motion,
    std::size_t begin, std::size_t end)
{
    if (!any_of_motion(motion, Motion::kinematic, begin, end)) return;
    for (std::size_t i = begin; i < end; ++i)
        if (motion[i] == Motion::kinematic) move_kinematic_body(x, i);
}

/// The integrators' corrector loop (Gear-5's corrector, Verlet's second
/// half) over every body, on body_blocks' blocks: body(kind, b, e) on each
/// run [b, e) of dynamic bodies, at most integrate_block long, and for the
/// grains rotation(b, e) on each run of dynamic grains of the same
/// integrate_block. Returns whether every body(…) returned true (an and, in
/// no order).
template <class Body, class Rotation>
bool all_dynamic_runs(World& w, ThreadPool& pool, Body&& body, Rotation&& rotation)
{
    const std::vector<Motion>& grain_motion = w.of(BodyKind::grain).motion;
    WIREDEM_ASSERT(w.grain_rotation.orientation.size() == grain_motion.size(), "every grain has a rotation");
    std::atomic<bool> all{true};
    body_blocks(w, pool, [&](std::size_t k, std::size_t begin, std::size_t end) {
        const std::vector<Motion>& motion = w.bodies[k].motion;
        bool ok = true;
        for (std::size_t block = begin; block < end; block += integrate_block) {
            const std::size_t block_end = std::min(end, block + integrate_block);
            for_each_run(motion, Motion::dynamic, block, block_end, [&](std::size_t b, std::size_t e) {
                ok = body(k, b, e) && ok;
            });
            if (k == static_cast<std::size_t>(BodyKind::grain))
                for_each_run(grain_motion, Motion::dynamic, block, block_end, rotation);
        }
        if (!ok) all.store(false, std::memory_order_relaxed);
    });
    return all.load();
}

} // namespace wiredem::engine
