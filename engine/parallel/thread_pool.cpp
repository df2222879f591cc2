#include "parallel/thread_pool.hpp"

#include <algorithm>
#include <cassert>
#include <limits>

#include <pthread.h>

namespace wiredem::engine {
namespace {

/// Busy-wait hint: lets the sibling hyper-thread run and saves power, without
/// giving the core away (no system call).
inline void cpu_relax() noexcept
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#elif defined(__aarch64__)
    asm volatile("yield");
#endif
}

/// Pause loops a worker spins for the next loop before it sleeps: ~0.1 ms,
/// longer than the serial gaps between the loops of one step, short enough
/// that an idle pool (between runs, or on a busy machine) leaves the core to
/// others.
constexpr int spin_before_sleep = 4000;

constexpr std::uint64_t pack(std::uint32_t loop, std::uint32_t unclaimed) noexcept
{
    return static_cast<std::uint64_t>(loop) << 32 | unclaimed;
}
constexpr std::uint32_t loop_of(std::uint64_t ticket) noexcept { return static_cast<std::uint32_t>(ticket >> 32); }
constexpr std::uint32_t unclaimed_of(std::uint64_t ticket) noexcept { return static_cast<std::uint32_t>(ticket); }

} // namespace

ThreadPool::ThreadPool(unsigned threads)
{
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    workers_.reserve(threads - 1);
    for (unsigned t = 1; t < threads; ++t) {
        workers_.emplace_back([this] { worker_loop(); });
        // Named, so that `top -H`, a debugger or a test can tell them apart.
        pthread_setname_np(workers_.back().native_handle(), worker_thread_name);
    }
}

ThreadPool::~ThreadPool()
{
    stop_.store(true);
    loop_.fetch_add(1); // wakes the spinners; notify_all the sleepers
    loop_.notify_all();
    for (auto& w : workers_) w.join();
}

void ThreadPool::run_chunks(std::uint32_t loop)
{
    // The chunks this thread ran, reported once when it leaves the loop: one
    // write to the shared counter per thread and loop, not one per chunk
    // (each is a cache line passed between the cores).
    std::uint32_t finished = 0;
    std::uint64_t ticket = ticket_.load(std::memory_order_acquire);
    for (;;) {
        if (loop_of(ticket) != loop || unclaimed_of(ticket) == 0) break;
        if (!ticket_.compare_exchange_weak(ticket, ticket - 1, std::memory_order_acquire, std::memory_order_acquire))
            continue; // another thread claimed one, or a new loop began: look again
        // Claimed: the caller waits for this chunk, so the loop's fields stay.
        const std::size_t c = chunks_ - unclaimed_of(ticket);
        const std::size_t begin = c * chunk_;
        (*body_)(begin, std::min(begin + chunk_, n_));
        ++finished;
        ticket = ticket_.load(std::memory_order_acquire);
    }
    if (finished != 0) done_.fetch_add(finished, std::memory_order_release);
}

void ThreadPool::worker_loop()
{
    std::uint32_t seen = 0;
    for (;;) {
        std::uint32_t loop = loop_.load(std::memory_order_acquire);
        for (int spins = 0; loop == seen; loop = loop_.load(std::memory_order_acquire)) {
            if (++spins < spin_before_sleep) {
                cpu_relax();
                continue;
            }
            // Sleep. The caller stores loop_ before it reads sleepers_, and we
            // count ourselves before we read loop_ (both sequentially
            // consistent): either it sees us and notifies, or we see its loop.
            sleepers_.fetch_add(1);
            if (loop_.load() == seen) loop_.wait(seen);
            sleepers_.fetch_sub(1);
            spins = 0;
        }
        if (stop_.load()) return;
        seen = loop;
        run_chunks(loop);
    }
}

void ThreadPool::for_chunks(std::size_t n, std::size_t chunk,
    const std::function<void(std::size_t, std::size_t)>& body)
{
    chunk = std::max<std::size_t>(chunk, 1);
    const std::size_t chunks = (n + chunk - 1) / chunk;
    assert(chunks < std::numeric_limits<std::uint32_t>::max());
    if (chunks == 0) return;
    body_ = &body;
    n_ = n;
    chunk_ = chunk;
    chunks_ = static_cast<std::uint32_t>(chunks);
    done_.store(0, std::memory_order_relaxed);
    const std::uint32_t loop = loop_.load(std::memory_order_relaxed) + 1;
    ticket_.store(pack(loop, chunks_), std::memory_order_release);
    loop_.store(loop);
    if (sleepers_.load() != 0) loop_.notify_all();
    run_chunks(loop);
    // Only chunks that a worker claimed can still be running.
    for (int spins = 0; done_.load(std::memory_order_acquire) != chunks_;)
        if (++spins < 64) cpu_relax();
        else std::this_thread::yield();
}

} // namespace wiredem::engine
