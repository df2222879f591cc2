// A fixed set of worker threads that runs parallel loops over index ranges.
//
// The engine's determinism does not depend on how a loop is split: every loop
// body writes only its own slots, and reductions go through fixed-size blocks
// (see reduce_blocks), so a result is the same for any thread count.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace wiredem::engine {

/// Worker threads for parallel_for. Not copyable. One loop runs at a time: a
/// pool must not be used from two threads at once.
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
    void worker_loop();
    void run_chunks();

    // A loop is published by bumping generation_; workers spin on it for a
    // short while (steps come back to back) before sleeping on wake_. The
    // caller spins (yielding) until pending_ reaches zero.
    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_;
    const std::function<void(std::size_t, std::size_t)>* body_ = nullptr;
    std::size_t n_ = 0;
    std::size_t chunk_ = 1;
    std::atomic<std::size_t> next_{0};
    std::atomic<std::uint64_t> generation_{0};
    std::atomic<unsigned> pending_{0};
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
