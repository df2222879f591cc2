// The thread pool: every index visited once, reductions independent of threads.
#include "parallel/thread_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>

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
