// The thread pool: every index visited once, reductions independent of threads.
#include "parallel/thread_pool.hpp"

#include "parallel/body_blocks.hpp"
#include "state/world.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <signal.h>
#include <unistd.h>

using namespace wiredem::engine;

TEST(ThreadPool, ParallelForVisitsEveryIndexExactlyOnce)
{
    for (unsigned threads : {1u, 2u, 3u}) {
        ThreadPool pool(threads);
        for (std::size_t n : {0ul, 1ul, 255ul, 256ul, 257ul, 10000ul}) {
            std::vector<int> visits(n, 0);
            parallel_for(pool, n, [&](std::size_t i) { ++visits[i]; }, 7);
            for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(visits[i], 1) << "n=" << n << " i=" << i << " threads=" << threads;
        }
    }
}

TEST(ThreadPool, ALoopOfMoreChunksThanATicketCountsStillGetsChunksOfTheAskedSize)
{
    // 300 001 blocks of two: more than the 65 535 units a ticket counts, so
    // they are claimed several at a time; each call must still get one block.
    for (unsigned threads : {1u, 2u, 3u}) {
        ThreadPool pool(threads);
        const std::size_t n = 600001;
        std::vector<int> visits(n, 0);
        std::atomic<std::size_t> oversized{0};
        parallel_for_blocks(pool, n, 2, [&](std::size_t begin, std::size_t end) {
            if (end - begin > 2 || begin % 2 != 0) oversized.fetch_add(1);
            for (std::size_t i = begin; i < end; ++i) ++visits[i];
        });
        EXPECT_EQ(oversized.load(), 0u) << "threads=" << threads;
        EXPECT_EQ(std::count(visits.begin(), visits.end(), 1), static_cast<long>(n)) << "threads=" << threads;
    }
}

TEST(ThreadPool, APartsLoopCutsEveryPartIntoTheBlocksOfItsOwnLoop)
{
    // Parts of 0, 5, 1000 and 257 items in blocks of 128: each part's blocks
    // start at its own 0 (as parallel_for_blocks cuts it), each once.
    const std::array<std::size_t, 4> sizes{0, 5, 1000, 257};
    std::vector<std::array<std::size_t, 3>> expected;
    for (std::size_t p = 0; p < sizes.size(); ++p)
        for (std::size_t b = 0; b < sizes[p]; b += 128) expected.push_back({p, b, std::min(b + 128, sizes[p])});
    for (unsigned threads : {1u, 2u, 3u}) {
        ThreadPool pool(threads);
        std::mutex m;
        std::vector<std::array<std::size_t, 3>> seen;
        parallel_for_parts(pool, sizes, 128, [&](std::size_t part, std::size_t begin, std::size_t end) {
            const std::lock_guard<std::mutex> lock(m);
            seen.push_back({part, begin, end});
        });
        std::sort(seen.begin(), seen.end());
        EXPECT_EQ(seen, expected) << "threads=" << threads;
    }
}

TEST(ThreadPool, BlockReductionIsBitIdenticalForAnyThreadCount)
{
    // Terms of very different magnitude: any change of summation order shows.
    std::vector<double> terms(100000);
    for (std::size_t i = 0; i < terms.size(); ++i) terms[i] = std::sin(1.0 + i) * std::pow(10.0, static_cast<double>(i % 17));
    auto sum_with = [&](unsigned threads) {
        ThreadPool pool(threads);
        return reduce_blocks(
            pool, terms.size(), 0.0,
            [&](std::size_t b, std::size_t e) {
                double s = 0.0;
                for (std::size_t i = b; i < e; ++i) s += terms[i];
                return s;
            },
            [](double a, double b) { return a + b; });
    };
    const double one = sum_with(1);
    EXPECT_EQ(sum_with(2), one);
    EXPECT_EQ(sum_with(4), one);
}

TEST(ThreadPool, ManyBackToBackLoopsComplete)
{
    ThreadPool pool(2);
    std::atomic<long> total{0};
    for (int loop = 0; loop < 2000; ++loop)
        parallel_for(pool, 1000, [&](std::size_t) { total.fetch_add(1, std::memory_order_relaxed); }, 64);
    EXPECT_EQ(total.load(), 2000L * 1000L);
}

namespace {
// A worker held in a signal handler stands for one the system has not
// scheduled (a busy machine, more threads than cores): the pool must not wait
// for it.
std::atomic<bool> hold_worker{false};
std::atomic<bool> worker_held{false};
extern "C" void hold_in_handler(int)
{
    worker_held.store(true);
    while (hold_worker.load()) {
    }
    worker_held.store(false);
}

/// Thread ids of this process's pool workers (by their name).
std::vector<pid_t> worker_threads()
{
    std::vector<pid_t> tids;
    for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) {
        std::ifstream comm(entry.path() / "comm");
        std::string name;
        std::getline(comm, name);
        if (name == worker_thread_name) tids.push_back(std::stoi(entry.path().filename().string()));
    }
    return tids;
}
} // namespace

TEST(ThreadPool, LoopsFinishWhileAWorkerCannotRun)
{
    ThreadPool pool(2);
    const std::vector<pid_t> workers = worker_threads();
    ASSERT_EQ(workers.size(), 1u) << "expected one thread named " << worker_thread_name;
    struct sigaction action {}, previous {};
    action.sa_handler = hold_in_handler;
    ASSERT_EQ(sigaction(SIGUSR1, &action, &previous), 0);
    hold_worker.store(true);
    ASSERT_EQ(tgkill(getpid(), workers[0], SIGUSR1), 0);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!worker_held.load() && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    if (!worker_held.load()) { // a sanitizer runtime may defer the signal while the worker sleeps
        hold_worker.store(false);
        sigaction(SIGUSR1, &previous, nullptr);
        GTEST_SKIP() << "the worker did not take the signal within 10 s";
    }
    // The loops run on the caller alone; an old pool waited for every worker
    // to check in, and hung here until the worker was released.
    auto loops = std::async(std::launch::async, [&pool] {
        long visited = 0;
        for (int loop = 0; loop < 100; ++loop) {
            std::vector<char> seen(1000, 0);
            parallel_for(pool, seen.size(), [&](std::size_t i) { seen[i] = 1; }, 10);
            visited += std::count(seen.begin(), seen.end(), 1);
        }
        return visited;
    });
    const bool finished = loops.wait_for(std::chrono::seconds(10)) == std::future_status::ready;
    hold_worker.store(false); // let the worker go (and a hung pool finish) either way
    EXPECT_TRUE(finished) << "100 loops did not finish in 10 s while the worker was held";
    EXPECT_EQ(loops.get(), 100L * 1000L);
    while (worker_held.load()) std::this_thread::yield();
    sigaction(SIGUSR1, &previous, nullptr);
    // And the worker takes part again.
    std::atomic<long> total{0};
    parallel_for(pool, 100000, [&](std::size_t) { total.fetch_add(1, std::memory_order_relaxed); }, 64);
    EXPECT_EQ(total.load(), 100000L);
}

TEST(ThreadPool, EachThreadStartsOnItsOwnRange)
{
    // Each thread's first chunk waits until the other thread has begun one
    // too, so both threads are in the loop before either could take a second
    // chunk. A pool that deals chunks to whichever thread asks next gives the
    // worker chunk 1; this one gives each thread the start of its own half
    // (the caller 0, the worker 4), so that every loop of a step works each
    // thread's half of the arrays, which its core's cache still holds.
    ThreadPool pool(2);
    constexpr std::size_t chunks = 8;
    const auto caller = std::this_thread::get_id();
    std::mutex mutex;
    std::map<std::thread::id, std::size_t> first_chunk;
    std::atomic<int> started{0};
    parallel_for_blocks(pool, chunks, 1, [&](std::size_t begin, std::size_t) {
        bool first = false;
        {
            const std::lock_guard lock(mutex);
            first = first_chunk.emplace(std::this_thread::get_id(), begin).second;
        }
        if (!first) return;
        started.fetch_add(1);
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (started.load() < 2 && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    });
    if (first_chunk.size() < 2) GTEST_SKIP() << "the worker did not take part within 10 s";
    for (const auto& [thread, chunk] : first_chunk)
        EXPECT_EQ(chunk, thread == caller ? 0u : chunks / 2) << (thread == caller ? "caller" : "worker");
}

namespace {

/// A world of 1000 grains, 600 wire nodes and 2000 membrane nodes (4, 3 and 8 blocks of body_block).
World bodies_of_three_kinds()
{
    World w;
    add_material(w, Material{});
    for (int i = 0; i < 1000; ++i) (void)add_grain(w, Vec3(0.01 * i, 0.0, 0.0), 1e-3, 0);
    for (int i = 0; i < 600; ++i) (void)add_node(w, BodyKind::wire, Vec3(0.01 * i, 1.0, 0.0), 1e-3, 1e-6, 0);
    for (int i = 0; i < 2000; ++i) (void)add_node(w, BodyKind::membrane, Vec3(0.01 * i, 2.0, 0.0), 1e-3, 1e-6, 0);
    return w;
}

} // namespace

TEST(BodyBlocks, VisitEveryBodyOnceInBlocksOfBodyBlock)
{
    const World w = bodies_of_three_kinds();
    for (unsigned threads : {1u, 2u, 3u}) {
        ThreadPool pool(threads);
        std::array<std::vector<std::atomic<int>>, body_kind_count> visits;
        for (std::size_t k = 0; k < body_kind_count; ++k) visits[k] = std::vector<std::atomic<int>>(w.bodies[k].size());
        std::atomic<bool> aligned{true};
        body_blocks(w, pool, [&](std::size_t k, std::size_t begin, std::size_t end) {
            if (begin % body_block != 0 || end - begin > body_block || (end - begin < body_block && end != w.bodies[k].size()))
                aligned = false;
            for (std::size_t i = begin; i < end; ++i) visits[k][i].fetch_add(1);
        });
        EXPECT_TRUE(aligned.load()) << threads << " threads";
        for (std::size_t k = 0; k < body_kind_count; ++k)
            EXPECT_TRUE(std::all_of(visits[k].begin(), visits[k].end(), [](const std::atomic<int>& v) { return v.load() == 1; }))
                << "kind " << k << ", " << threads << " threads";
    }
}

TEST(BodyBlocks, EachThreadStartsOnItsShareOfEveryKind)
{
    // As ThreadPool.EachThreadStartsOnItsOwnRange: each thread's first block
    // waits until the other has begun one. The worker's first block is the
    // first of its half of the grains (block 2 of 4), not a block of the
    // flat order's second half (wire nodes): the thread that gathers a
    // body's force is the one that corrects it, and each gets half of the
    // grains, the heavier bodies.
    const World w = bodies_of_three_kinds();
    ThreadPool pool(2);
    const auto caller = std::this_thread::get_id();
    std::mutex mutex;
    std::map<std::thread::id, std::pair<std::size_t, std::size_t>> first_block; // (kind, begin)
    std::atomic<int> started{0};
    body_blocks(w, pool, [&](std::size_t k, std::size_t begin, std::size_t) {
        bool first = false;
        {
            const std::lock_guard lock(mutex);
            first = first_block.emplace(std::this_thread::get_id(), std::pair{k, begin}).second;
        }
        if (!first) return;
        started.fetch_add(1);
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (started.load() < 2 && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    });
    if (first_block.size() < 2) GTEST_SKIP() << "the worker did not take part within 10 s";
    for (const auto& [thread, block] : first_block) {
        EXPECT_EQ(block.first, 0u);
        EXPECT_EQ(block.second, thread == caller ? 0u : 2 * body_block) << (thread == caller ? "caller" : "worker");
    }
}
