// A fixed set of worker threads that runs parallel loops over index ranges.
//
// The engine's determinism does not depend on how a loop is split: every loop
// body writes only its own slots, and reductions go through fixed-size blocks
// (see reduce_blocks), so a result is the same for any thread count.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

namespace wiredem::engine {

/// Name of every worker thread (as /proc/<pid>/task/<tid>/comm shows it).
inline constexpr char worker_thread_name[] = "wiredem-worker";

/// Worker threads for parallel_for. Not copyable. One loop runs at a time: a
/// pool must not be used from two threads at once.
///
/// A loop is a set of chunks that threads claim one at a time; the caller
/// claims chunks too and waits only for chunks that another thread has
/// claimed and not finished. A worker that has not woken up yet when the
/// chunks run out (the machine is busy, or it was asleep) takes no part and
/// costs the loop nothing: on a loaded machine a loop is never slower than on
/// the caller alone.
///
/// The chunks are dealt in as many contiguous ranges as there are threads,
/// and each thread claims from its own range first (the caller the first,
/// worker k the (k+1)-th), then from the others'. So as long as the threads
/// keep pace, a thread works on the same part of every array in every loop
/// of a step that cuts it alike (body_blocks, parallel/body_blocks.hpp: the
/// bodies it predicted are the ones it gathers and corrects), and that part
/// stays in its core's own cache instead of passing between the cores at
/// each loop.
class ThreadPool {
public:
    /// @param threads total threads taking part in a loop, the caller included;
    ///                0 means std::thread::hardware_concurrency().
    explicit ThreadPool(unsigned threads = 0);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    /// Threads taking part in a loop (workers + the calling thread), ≥ 1.
    [[nodiscard]] unsigned size() const { return static_cast<unsigned>(workers_.size()) + 1; }

    /// Calls body(begin, end) on consecutive chunks of [0, n) of at most
    /// `chunk` items, spread over the threads; returns when all are done.
    void for_chunks(std::size_t n, std::size_t chunk,
        const std::function<void(std::size_t, std::size_t)>& body);

private:
    /// A range of a loop's units (a unit is one chunk, or several when a
    /// loop has more chunks than a ticket can count): one 64-bit ticket,
    /// the loop number << 32 | next unit << 16 | one past the range's last.
    /// On a cache line of its own: its owner claims from it without touching
    /// another thread's line.
    struct alignas(64) Range {
        std::atomic<std::uint64_t> ticket{0};
    };

    void worker_loop(unsigned self);
    /// Claims and runs units of loop `loop`, from range `self` first, until
    /// none is left (or another loop has been published).
    void run_chunks(std::uint32_t loop, unsigned self);

    std::vector<std::thread> workers_;

    // The published loop. Written by the caller before it publishes the loop
    // number in the ranges' tickets, and read by a thread only after it has
    // claimed a unit: the caller does not return (and write the next loop)
    // until every claimed unit is done, so these need no atomics.
    const std::function<void(std::size_t, std::size_t)>* body_ = nullptr;
    std::size_t n_ = 0;
    std::size_t chunk_ = 1;
    std::size_t chunks_per_unit_ = 1;
    std::uint32_t units_ = 0;

    // One range per thread. A unit is claimed by a compare-exchange on its
    // range's ticket, which holds the loop number, the next unit and the
    // range's end together: no thread can claim a unit of a loop that has
    // ended, nor judge one loop's ticket by another's end. done_ counts
    // finished units.
    std::unique_ptr<Range[]> ranges_;
    alignas(64) std::atomic<std::uint32_t> done_{0};
    // Workers spin on loop_ for a short while between loops (a step's loops
    // come back to back), then sleep on it (atomic wait: a futex).
    alignas(64) std::atomic<std::uint32_t> loop_{0};
    std::atomic<unsigned> sleepers_{0};
    std::atomic<bool> stop_{false};
};

/// Runs f(i) for every i in [0, n). Small loops run on the calling thread.
template <class F>
void parallel_for(ThreadPool& pool, std::size_t n, F&& f, std::size_t chunk = 256)
{
    if (pool.size() == 1 || n <= chunk) {
        for (std::size_t i = 0; i < n; ++i) f(i);
        return;
    }
    const std::function<void(std::size_t, std::size_t)> body = [&f](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) f(i);
    };
    pool.for_chunks(n, chunk, body);
}

/// Runs f(begin, end) on consecutive blocks [begin, end) of at most `block`
/// items covering [0, n), spread over the threads (on the calling thread alone
/// for one thread or one block). For loops whose body works a block at a time.
template <class F>
void parallel_for_blocks(ThreadPool& pool, std::size_t n, std::size_t block, F&& f)
{
    if (pool.size() == 1 || n <= block) {
        for (std::size_t begin = 0; begin < n; begin += block) f(begin, begin + block < n ? begin + block : n);
        return;
    }
    const std::function<void(std::size_t, std::size_t)> body = [&f](std::size_t b, std::size_t e) { f(b, e); };
    pool.for_chunks(n, block, body);
}

/// Runs f(part, begin, end) on consecutive blocks [begin, end) of at most
/// `block` items covering [0, sizes[part]) of every part, all parts' blocks
/// in one loop over the threads (in part order on the calling thread alone
/// for one thread or one block). Each part is cut into the blocks
/// parallel_for_blocks would cut it into alone, so a body that works block by
/// block computes the same; the parts share one loop, and one wait for the
/// slowest thread, instead of one each: the engine's per-kind loops (grains,
/// wire nodes, membrane nodes, grains' rotations) of a step are short at the
/// paper's size (a few tens of microseconds), and a loop's start and join
/// cost about as much on two threads as a small loop's work.
template <std::size_t Parts, class F>
void parallel_for_parts(ThreadPool& pool, const std::array<std::size_t, Parts>& sizes, std::size_t block, F&& f)
{
    std::array<std::size_t, Parts + 1> first_block{}; // index of each part's first block
    for (std::size_t p = 0; p < Parts; ++p) first_block[p + 1] = first_block[p] + (sizes[p] + block - 1) / block;
    const std::size_t blocks = first_block[Parts];
    const auto run = [&](std::size_t b) {
        std::size_t p = 0;
        while (b >= first_block[p + 1]) ++p;
        const std::size_t begin = (b - first_block[p]) * block;
        f(p, begin, begin + block < sizes[p] ? begin + block : sizes[p]);
    };
    if (pool.size() == 1 || blocks <= 1) {
        for (std::size_t b = 0; b < blocks; ++b) run(b);
        return;
    }
    const std::function<void(std::size_t, std::size_t)> body = [&run](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) run(i);
    };
    pool.for_chunks(blocks, 1, body);
}

/// Block size of every deterministic reduction in the engine. Fixed, so that
/// the order of floating-point additions never depends on the thread count.
inline constexpr std::size_t reduction_block = 1024;

/// Deterministic reduction: partial(begin, end) is evaluated on fixed blocks of
/// `reduction_block` items (in parallel) and the partials are combined with
/// `combine` in block order on the calling thread.
template <class T, class Partial, class Combine>
[[nodiscard]] T reduce_blocks(ThreadPool& pool, std::size_t n, T init, Partial&& partial, Combine&& combine)
{
    const std::size_t blocks = (n + reduction_block - 1) / reduction_block;
    std::vector<T> partials(blocks, init);
    parallel_for(
        pool, blocks,
        [&](std::size_t b) {
            const std::size_t begin = b * reduction_block;
            const std::size_t end = begin + reduction_block < n ? begin + reduction_block : n;
            partials[b] = partial(begin, end);
        },
        1);
    T total = init;
    for (const T& p : partials) total = combine(total, p);
    return total;
}

} // namespace wiredem::engine
