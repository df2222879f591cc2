// Everything the server is configured with, filled from the command line in
// main.cpp and read-only afterwards (safe to read from any thread).
#pragma once

#include "slurm.hpp"

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace wiredem::server {

struct ServerConfig {
    std::string listen_host = "127.0.0.1";     ///< address to bind; loopback unless asked otherwise
    std::uint16_t listen_port = 8080;          ///< 0: any free port (see port_file); the bound port once listening
    /// Names besides the listen address (and localhost on loopback) that a
    /// request's Host may give (--allowed-host; server/origin.hpp).
    std::vector<std::string> allowed_hosts;
    std::filesystem::path data_dir = "wiredem-data";  ///< database and job files
    std::filesystem::path runner;              ///< runner executable (absolute)
    std::filesystem::path port_file;           ///< if set, the bound port is written here once listening
    unsigned concurrent_jobs = 1;              ///< jobs run at the same time
    unsigned threads_per_job = 1;              ///< engine threads of each job
    unsigned io_threads = 2;                   ///< threads serving HTTP
    unsigned submit_threads = 1;               ///< threads validating submitted specs (off the I/O threads)
    unsigned data_threads = 2;                 ///< threads reading result files for the data routes (off the I/O threads)
    std::size_t max_pending_submits = 64;      ///< submits waiting for those; more get 503
    std::size_t max_queued = 100;              ///< queued jobs before POST answers 429
    /// Ended jobs kept (a study's excepted): past it, the oldest go with their
    /// files as new jobs come (0: keep all).
    std::size_t max_finished_jobs = 1000;
    std::size_t max_study_points = 256;        ///< jobs one study may create (its grid's points)
    std::uint64_t max_bodies_per_job = 2'000'000;  ///< estimated bodies (grains + wire + membrane) per job
    /// Estimated time steps of a job, preparation and tests (api::estimated_work):
    /// 2·10⁷ is ~10 times a paper-size campaign's.
    double max_steps_per_job = 2e7;
    double max_samples_per_test = 1e6;         ///< estimated rows of one test's time series
    /// Wall-clock limit of one attempt of a job (0: none): 48 h, ~20 paper-size
    /// campaigns on 2 cores.
    std::chrono::seconds max_job_duration{48 * 3600};
    /// Wall time between a running test's checkpoints, passed to the runner
    /// [s]; another attempt of the job continues from the last one.
    double checkpoint_interval_s = 300.0;
    std::uint64_t max_body_bytes = 1 << 20;    ///< request body limit [bytes] (413 above)
    std::uint32_t max_header_bytes = 16 << 10; ///< request header limit [bytes] (431 above)
    /// A connection with nothing of a request received (new, or kept alive
    /// between requests) is closed after this.
    std::chrono::seconds idle_timeout{10};
    std::chrono::seconds read_timeout{30};     ///< a request, from its first byte, must be complete within this
    std::chrono::seconds write_timeout{60};    ///< limit for each chunk of a reply to drain
    /// Open connections; at the limit the longest idle one is closed for a
    /// newcomer, who gets 503 when none is idle.
    std::size_t max_connections = 512;
    std::chrono::seconds retry_after{30};      ///< Retry-After sent with 429
    std::string token;                         ///< bearer token for /v1 routes; empty: no auth
    /// Set with --executor slurm: jobs run as Slurm jobs (server/slurm.hpp).
    std::optional<SlurmOptions> slurm;
    /// The installed web page served at `/` (handlers/static_files.hpp); empty: none.
    std::filesystem::path web_dir;
};

} // namespace wiredem::server
