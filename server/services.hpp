// What a handler may use: the configuration, the job store, the queue and the
// counters. Handlers get it by reference; all members are thread-safe.
#pragma once

#include "config.hpp"
#include "job_queue.hpp"
#include "job_store.hpp"

#include <atomic>
#include <chrono>
#include <cstdint>

namespace wiredem::server {

/// Counters shown by /metrics. Relaxed atomics: exact ordering does not matter.
struct Metrics {
    /// Replies by status class: index 1 = 1xx … 5 = 5xx.
    std::atomic<std::uint64_t> responses_by_class[6]{};
    std::atomic<std::uint64_t> jobs_submitted{0};
    std::atomic<std::uint64_t> connections_open{0};
    std::atomic<std::uint64_t> connections_rejected{0};
    std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
};

struct Services {
    const ServerConfig& config;
    JobStore& store;
    JobQueue& queue;
    Metrics& metrics;
};

} // namespace wiredem::server
