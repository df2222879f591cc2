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
    std::atomic<std::uint64_t> jobs_submitted{0};        ///< 201s that created a job
    std::atomic<std::uint64_t> connections_open{0};      ///< live sessions
    std::atomic<std::uint64_t> connections_rejected{0};  ///< closed at once: max_connections reached
    std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();  ///< for uptime
};

/// Everything a handler may use; references to objects that outlive the
/// I/O threads.
struct Services {
    const ServerConfig& config;  ///< read-only after start
    JobStore& store;             ///< durable job table
    JobQueue& queue;             ///< workers and live progress
    Metrics& metrics;            ///< counters for /metrics
};

} // namespace wiredem::server
