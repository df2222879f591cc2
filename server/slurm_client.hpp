// Slurm's commands as the executor uses them: sbatch, squeue, sacct, scancel,
// each run with an argument vector (fork/exec, no shell; server/child_process.hpp)
// and a time limit. Found on PATH when the server starts; SLURM_CONF and the
// rest of the server's environment reach them, and through sbatch the jobs.
#pragma once

#include "slurm.hpp"

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace wiredem::server {

/// What a command did.
struct CommandResult {
    int status = -1;         ///< wait status
    std::string out;         ///< its stdout
    std::string err;         ///< the last KiB of its stderr
    [[nodiscard]] bool ok() const;
};

/// Runs `argv` (argv[0] absolute) in `/`, killing it after `limit`.
/// @throws std::system_error when it cannot be started
[[nodiscard]] CommandResult run_command(const std::vector<std::string>& argv, std::chrono::seconds limit);

/// The executable `name` in a folder of PATH; empty when there is none.
[[nodiscard]] std::filesystem::path find_on_path(const std::string& name);

/// A job's Slurm jobs: submission, their states, cancellation.
class SlurmClient {
public:
    /// Finds sbatch, squeue and scancel (and sacct if installed) on PATH,
    /// and asks the controller (squeue) whether it answers.
    /// @throws std::runtime_error naming what is missing, or squeue's error
    explicit SlurmClient(SlurmOptions options);

    [[nodiscard]] const SlurmOptions& options() const { return options_; }

    /// Writes the three batch scripts into files.dir() and submits them
    /// (prepare; the tests' array afterok it; analyse afterok the array).
    /// When a later sbatch fails, the earlier Slurm jobs are cancelled.
    /// @throws std::runtime_error with sbatch's message
    [[nodiscard]] SlurmIds submit(const std::string& job_id, const SlurmFiles& files, std::size_t tests,
        double checkpoint_interval_s);

    /// What squeue knows of the Slurm jobs named for `job_id`, and for those
    /// of `ids` it no longer lists, what sacct knows (when accounting is kept).
    /// @throws std::runtime_error when squeue fails (the controller is down)
    [[nodiscard]] std::vector<SlurmJobLine> query(const std::string& job_id, const SlurmIds& ids);

    /// Cancels Slurm jobs (scancel); best effort, a failure is logged.
    void cancel(const std::vector<std::int64_t>& slurm_jobs);

    /// Cancels the pending or running Slurm jobs named for `job_id` other
    /// than `keep`'s: those of an attempt whose ids the store never got (the
    /// server died between sbatch and the store) or that Slurm had lost.
    void cancel_strays(const std::string& job_id, const SlurmIds* keep);

private:
    SlurmOptions options_;
    std::filesystem::path sbatch_, squeue_, scancel_, sacct_;
};

} // namespace wiredem::server
