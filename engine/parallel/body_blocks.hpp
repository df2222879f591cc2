// The one cut of the bodies into blocks that a step's per-body loops share.
#pragma once

#include "core/types.hpp"
#include "parallel/thread_pool.hpp"
#include "state/world.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace wiredem::engine {

/// Bodies per block of a step's per-body loops (body_blocks).
inline constexpr std::size_t body_block = 256;

/// Runs f(kind, begin, end) on blocks [begin, end) of at most body_block
/// bodies of every kind (grains, wire nodes, membrane nodes; kind as a
/// std::size_t), all in one loop over the threads.
///
/// Every loop of a step that works on each body's own slots — the
/// predictor, the test of the bodies' moves, the gather, the corrector, of
/// either integrator — runs on these blocks, a grain's rotation in its
/// grain's block, and the blocks are dealt so that each thread starts on
/// the same share of every kind in every such loop: thread r on blocks
/// [r·B/T, (r+1)·B/T) of each kind's B blocks (the pool gives thread r the
/// r-th of T contiguous ranges of a loop, ThreadPool; the order below puts
/// thread r's share of every kind into its range, to within a block at a
/// range's ends). While the threads keep pace, the bodies whose forces a
/// thread gathers are the ones it corrects and predicts, their arrays stay
/// in its core's cache, and as the wire's and the membrane's stages deal
/// their nodes in order too (blocks of nodes, blocks of rows), a thread
/// computes the wire and membrane forces of roughly the nodes it
/// integrates. Each thread gets a share of every kind, so of the grains'
/// contacts and rotations, the heavier work per body, as much as the
/// others. (Each loop cut by its own blocks — the gather's of 256, the
/// integrators' of 128 with the grains' rotations a part of their own, all
/// dealt in flat order — split each loop at other bodies on two threads:
/// about 4000 bodies' forces and every grain's torque of the study's
/// column went from one core to the other at every step.) Which thread
/// runs a block never changes a bit: f writes each body's own slots.
template <class F>
void body_blocks(const World& w, ThreadPool& pool, F&& f)
{
    std::array<std::size_t, body_kind_count> sizes{};
    std::array<std::size_t, body_kind_count> blocks{};
    std::size_t total = 0;
    for (std::size_t k = 0; k < body_kind_count; ++k) {
        sizes[k] = w.bodies[k].size();
        blocks[k] = (sizes[k] + body_block - 1) / body_block;
        total += blocks[k];
    }
    const auto run = [&](std::size_t k, std::size_t block) {
        const std::size_t begin = block * body_block;
        f(k, begin, std::min(begin + body_block, sizes[k]));
    };
    const std::size_t threads = pool.size();
    if (threads == 1 || total <= 1) {
        for (std::size_t k = 0; k < body_kind_count; ++k)
            for (std::size_t block = 0; block < blocks[k]; ++block) run(k, block);
        return;
    }
    // The loop's blocks: thread 0's share of every kind, in kind order, then thread 1's, …
    std::vector<std::pair<std::size_t, std::size_t>> order; // (kind, block)
    order.reserve(total);
    for (std::size_t r = 0; r < threads; ++r)
        for (std::size_t k = 0; k < body_kind_count; ++k)
            for (std::size_t block = blocks[k] * r / threads; block < blocks[k] * (r + 1) / threads; ++block)
                order.emplace_back(k, block);
    const std::function<void(std::size_t, std::size_t)> body = [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) run(order[i].first, order[i].second);
    };
    pool.for_chunks(total, 1, body);
}

} // namespace wiredem::engine
