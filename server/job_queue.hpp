// The simulation workers. Each worker thread claims the oldest queued job from
// the store and runs it as a child process (the runner contract in
// docs/api.md): crash isolation, cancellation by signal, and a kill -9 of the
// server never leaves a job reported as succeeded without its files.
//
// Workers are plain std::threads: they never run on the HTTP I/O threads, and
// the only thing the I/O threads ask of the queue (notify, cancel, live) takes
// a mutex for microseconds.
//
// Files of job <id>, all under <data-dir>/jobs/<id>/:
//   work/job.json, work/out/...   the current attempt (wiped at every attempt)
//   summary.json, result.h5       moved in by rename only after the runner
//                                 exited 0 and both exist; then the store says
//                                 succeeded.
//   work/slurm/...                with --executor slurm: the stages' batch
//                                 scripts, logs and exit files (slurm.hpp)
#pragma once

#include "job_store.hpp"
#include "slurm.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace wiredem::server {

class ChildProcess;
class SlurmClient;

/// The job directory (campaign/files.hpp) of job `id`'s current attempt: the
/// runner's -o, where its per-test files appear while it runs.
[[nodiscard]] std::filesystem::path attempt_output_dir(const std::filesystem::path& data_dir, const std::string& id);

/// How the queue runs jobs.
struct QueueConfig {
    std::filesystem::path data_dir;        ///< holds jobs/<id>/
    std::filesystem::path runner;          ///< executable following the runner contract
    unsigned concurrent_jobs = 1;          ///< worker threads, ≥ 1
    unsigned threads_per_job = 1;          ///< passed to the runner as --threads
    int max_attempts = 5;                  ///< attempts interrupted by crashes before giving up
    /// Attempts a job gets when its runner is killed by a SIGKILL the server
    /// did not send (likely the OOM killer): one retry.
    int attempts_after_sigkill = 2;
    std::chrono::milliseconds kill_grace{3000};  ///< SIGTERM → SIGKILL delay
    /// An attempt running longer than this is stopped (SIGTERM, then SIGKILL)
    /// and its job fails saying so; 0: no limit.
    std::chrono::seconds max_job_duration{0};
    /// Passed to the runner as --checkpoint-interval: wall time between a
    /// test's checkpoints [s]. Another attempt of a job continues from them.
    double checkpoint_interval_s = 300.0;
    /// Set: jobs run as Slurm jobs (`--executor slurm`, server/slurm.hpp):
    /// a worker submits a job's stages with sbatch and follows them, and
    /// concurrent_jobs bounds the jobs in Slurm at once. max_job_duration
    /// does not apply (the Slurm jobs have their own time limit).
    std::optional<SlurmOptions> slurm = std::nullopt;
};

/// The freshest progress of a running job (kept in memory; the store gets a
/// copy at every stage change and at most every persist_interval).
struct LiveProgress {
    JobState state = JobState::preparing;
    std::string stage;
    double progress = 0.0;
    std::optional<double> eta_s;
    std::string message;
};

/// Runs queued jobs on worker threads, one runner process per job (or, with
/// the Slurm executor, one set of Slurm jobs per job).
class JobQueue {
public:
    /// @throws std::runtime_error when the Slurm executor is asked for and
    /// its commands are missing
    JobQueue(JobStore& store, QueueConfig config);
    ~JobQueue();  ///< calls stop()
    JobQueue(const JobQueue&) = delete;
    JobQueue& operator=(const JobQueue&) = delete;

    /// Requeues jobs interrupted by a crash, checks the files of succeeded
    /// jobs, sweeps what an interrupted clean-up left (sweep_leftovers), and
    /// starts the workers.
    void start();

    /// Wakes a worker: a job was queued. Thread-safe, non-blocking.
    void notify();

    /// Asks the runner of `id` (if one runs) to stop: SIGTERM now, SIGKILL
    /// after kill_grace; with the Slurm executor, its Slurm jobs are
    /// cancelled (by its worker, or here with scancel when no worker follows
    /// them yet). The caller has already marked the job cancelled.
    void cancel(const std::string& id);

    /// Stops claiming jobs, stops every runner and puts its job back in the
    /// queue, joins the workers. Blocks up to about kill_grace. Idempotent.
    void stop();

    /// Progress of `id` if a worker runs it now.
    [[nodiscard]] std::optional<LiveProgress> live(const std::string& id) const;

    /// Number of workers running a job.
    [[nodiscard]] unsigned busy_workers() const;

    /// Newest engine throughput reported by a runner [body-steps/s].
    [[nodiscard]] std::optional<double> body_steps_per_second() const;

    /// The configuration in force (concurrent_jobs and threads_per_job at least 1).
    [[nodiscard]] const QueueConfig& config() const { return config_; }

private:
    /// A job a worker has claimed; child is null until the runner started.
    struct Active {
        std::shared_ptr<ChildProcess> child;
        LiveProgress live;
        bool cancel_requested = false;
        std::chrono::steady_clock::time_point signalled_at{};
        bool signalled = false;
        bool timed_out = false;   ///< stopped for running past max_job_duration
    };

    void worker_loop(unsigned index);
    /// At start: removes the work folder of every job that has ended, and
    /// the folders no job names (a kill -9 during a clean-up, or between a
    /// DELETE's row and its folder, leaves them half removed).
    void sweep_leftovers();
    /// Registers a claimed job as active unless it was cancelled or the
    /// queue stops meanwhile (then it is requeued or its work removed).
    bool begin_attempt(const JobRecord& job);
    void run_job(const JobRecord& job);
    /// The Slurm executor's attempt (slurm_executor.cpp): submit, or follow
    /// the Slurm jobs the store has for it, until they end.
    void run_slurm_job(const JobRecord& job);
    /// Moves a finished campaign's files from work/out into the job's folder
    /// and marks it succeeded (or failed, when they are not sound).
    void publish(const JobRecord& job);
    void on_progress_line(const std::string& id, const std::string& line,
        std::chrono::steady_clock::time_point& last_persist);
    void finish_attempt(const JobRecord& job, int wait_status, const std::string& stderr_tail,
        bool cancelled, bool stopping, bool timed_out);

    JobStore& store_;
    QueueConfig config_;
    std::vector<std::thread> workers_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    bool stopping_ = false;
    bool started_ = false;
    std::uint64_t wake_count_ = 0;
    std::map<std::string, Active> active_;
    std::optional<double> body_steps_per_second_;
    std::unique_ptr<SlurmClient> slurm_;
};

} // namespace wiredem::server
