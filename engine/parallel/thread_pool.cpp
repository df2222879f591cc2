#include "parallel/thread_pool.hpp"

#include <algorithm>

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

/// A ticket counts units in 16 bits (next and end each): a loop of more
/// chunks claims them in units of several.
constexpr unsigned unit_bits = 16;
constexpr std::uint32_t max_units = (1u << unit_bits) - 1;
constexpr std::uint64_t one_unit = std::uint64_t{1} << unit_bits;

constexpr std::uint64_t pack(std::uint32_t loop, std::uint32_t next, std::uint32_t end) noexcept
{
    return static_cast<std::uint64_t>(loop) << 32 | static_cast<std::uint64_t>(next) << unit_bits | end;
}
constexpr std::uint32_t loop_of(std::uint64_t ticket) noexcept { return static_cast<std::uint32_t>(ticket >> 32); }
constexpr std::uint32_t next_of(std::uint64_t ticket) noexcept { return static_cast<std::uint32_t>(ticket >> unit_bits) & max_units; }
constexpr std::uint32_t end_of(std::uint64_t ticket) noexcept { return static_cast<std::uint32_t>(ticket) & max_units; }
static_assert(2 * unit_bits <= 32, "next and end share the ticket's low 32 bits");

} // namespace

ThreadPool::ThreadPool(unsigned threads)
{
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    ranges_ = std::make_unique<Range[]>(threads);
    workers_.reserve(threads - 1);
    for (unsigned t = 1; t < threads; ++t) {
        workers_.emplace_back([this, t] { worker_loop(t); });
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

void ThreadPool::run_chunks(std::uint32_t loop, unsigned self)
{
    // The units this thread ran, reported once when it leaves the loop: one
    // write to the shared counter per thread and loop, not one per unit
    // (each is a cache line passed between the cores).
    std::uint32_t finished = 0;
    const unsigned threads = size();
    for (unsigned k = 0; k < threads; ++k) {
        Range& range = ranges_[(self + k) % threads];
        std::uint64_t ticket = range.ticket.load(std::memory_order_acquire);
        for (;;) {
            if (loop_of(ticket) != loop || next_of(ticket) >= end_of(ticket)) break;
            if (!range.ticket.compare_exchange_weak(ticket, ticket + one_unit, std::memory_order_acquire,
                    std::memory_order_acquire))
                continue; // another thread claimed it, or a new loop began: look again
            // Claimed: the caller waits for this unit, so the loop's fields stay.
            const std::size_t first_chunk = std::size_t{next_of(ticket)} * chunks_per_unit_;
            for (std::size_t c = first_chunk; c < first_chunk + chunks_per_unit_; ++c) {
                const std::size_t begin = c * chunk_;
                if (begin >= n_) break;
                (*body_)(begin, std::min(begin + chunk_, n_));
            }
            ++finished;
            ticket = range.ticket.load(std::memory_order_acquire);
        }
    }
    if (finished != 0) done_.fetch_add(finished, std::memory_order_release);
}

void ThreadPool::worker_loop(unsigned self)
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
        run_chunks(loop, self);
    }
}

void ThreadPool::for_chunks(std::size_t n, std::size_t chunk,
    const std::function<void(std::size_t, std::size_t)>& body)
{
    chunk = std::max<std::size_t>(chunk, 1);
    const std::size_t chunks = (n + chunk - 1) / chunk;
    if (chunks == 0) return;
    body_ = &body;
    n_ = n;
    chunk_ = chunk;
    chunks_per_unit_ = (chunks + max_units - 1) / max_units;
    units_ = static_cast<std::uint32_t>((chunks + chunks_per_unit_ - 1) / chunks_per_unit_);
    done_.store(0, std::memory_order_relaxed);
    const std::uint32_t loop = loop_.load(std::memory_order_relaxed) + 1;
    // Range r holds units [r·U/T, (r+1)·U/T).
    const unsigned threads = size();
    for (unsigned r = 0; r < threads; ++r)
        ranges_[r].ticket.store(pack(loop, static_cast<std::uint32_t>(std::size_t{units_} * r / threads),
                                    static_cast<std::uint32_t>(std::size_t{units_} * (r + 1) / threads)),
            std::memory_order_release);
    loop_.store(loop);
    if (sleepers_.load() != 0) loop_.notify_all();
    run_chunks(loop, 0);
    // Only units that a worker claimed can still be running.
    for (int spins = 0; done_.load(std::memory_order_acquire) != units_;)
        if (++spins < 64) cpu_relax();
        else std::this_thread::yield();
}

} // namespace wiredem::engine
