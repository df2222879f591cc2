#include "parallel/thread_pool.hpp"

#include <algorithm>

namespace wiredem::engine {
namespace {
/// Spins before a worker sleeps: long enough to bridge the gap between two
/// parallel loops of one step, short enough not to burn a core between runs.
constexpr int spin_before_sleep = 20000;
} // namespace

ThreadPool::ThreadPool(unsigned threads)
{
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    workers_.reserve(threads - 1);
    for (unsigned t = 1; t < threads; ++t) workers_.emplace_back([this] { worker_loop(); });
}

ThreadPool::~ThreadPool()
{
    {
        std::lock_guard lock(mutex_);
        stop_.store(true);
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
}

void ThreadPool::run_chunks()
{
    for (;;) {
        const std::size_t begin = next_.fetch_add(chunk_, std::memory_order_relaxed);
        if (begin >= n_) return;
        (*body_)(begin, std::min(begin + chunk_, n_));
    }
}

void ThreadPool::worker_loop()
{
    std::uint64_t seen = 0;
    for (;;) {
        int spins = 0;
        while (generation_.load(std::memory_order_acquire) == seen && !stop_.load(std::memory_order_relaxed)) {
            if (++spins < spin_before_sleep) {
                if (spins > 64) std::this_thread::yield();
                continue;
            }
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_.load() || generation_.load() != seen; });
        }
        if (stop_.load()) return;
        seen = generation_.load(std::memory_order_acquire);
        run_chunks();
        pending_.fetch_sub(1, std::memory_order_acq_rel);
    }
}

void ThreadPool::for_chunks(std::size_t n, std::size_t chunk,
    const std::function<void(std::size_t, std::size_t)>& body)
{
    body_ = &body;
    n_ = n;
    chunk_ = std::max<std::size_t>(chunk, 1);
    next_.store(0, std::memory_order_relaxed);
    pending_.store(static_cast<unsigned>(workers_.size()), std::memory_order_relaxed);
    {
        std::lock_guard lock(mutex_); // pairs with the sleeping workers' predicate check
        generation_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_all();
    run_chunks();
    int spins = 0;
    while (pending_.load(std::memory_order_acquire) != 0)
        if (++spins > 64) std::this_thread::yield();
}

} // namespace wiredem::engine
