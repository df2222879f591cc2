// The Slurm executor's pure pieces (`wiredem-server --executor slurm`): the
// options and their validation, the batch scripts and sbatch command lines
// of a job's three Slurm jobs, what squeue says of them, and what the job's
// state is from that and the files of its directory. No process is started
// here (slurm_executor.hpp does that), so every piece is tested on its own
// (tests/server/test_slurm.cpp).
//
// A job is three Slurm jobs, each running one stage command of the campaign
// (docs/studies.md) in the job's folder, which every node must see (a
// shared file system):
//   prepare                       wiredem prepare work/job.json -o work/out
//   an array of tests, afterok    wiredem test work/out --index $SLURM_ARRAY_TASK_ID
//   analyse, afterok the array    wiredem analyse work/out
// Their stdout (JSON progress lines), stderr and exit status go to
// work/slurm/STAGE.out, .err and .exit (test_K.* for test K).
#pragma once

#include "job.hpp"

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace wiredem::server {

/// The server's Slurm options (--slurm-*, server/main.cpp).
struct SlurmOptions {
    std::string partition;                 ///< empty: the cluster's default
    std::string account;                   ///< empty: the user's default
    std::string time_limit;                ///< per Slurm job, in sbatch's --time forms; empty: the partition's
    unsigned cpus_per_task = 1;            ///< each stage's CPUs, passed to wiredem as --threads
    std::vector<std::string> sbatch_options; ///< more sbatch options, each one argument (--qos=high)
    std::filesystem::path wiredem;         ///< the wiredem binary the nodes run (absolute)
    std::chrono::milliseconds poll_interval{5000}; ///< between two looks at a job's Slurm jobs
};

/// The options' first problem, naming the option; nothing when they are usable.
[[nodiscard]] std::optional<std::string> slurm_options_problem(const SlurmOptions& options);

/// The three stages, in order.
enum class SlurmStage { prepare, test, analyse };

/// The files of one job's Slurm attempt, under its work folder.
struct SlurmFiles {
    std::filesystem::path work;            ///< DATA/jobs/ID/work (absolute)
    [[nodiscard]] std::filesystem::path job_json() const { return work / "job.json"; }
    [[nodiscard]] std::filesystem::path out() const { return work / "out"; }       ///< the campaign's job directory
    [[nodiscard]] std::filesystem::path dir() const { return work / "slurm"; }     ///< scripts, logs, exit markers
    [[nodiscard]] std::filesystem::path script(SlurmStage stage) const;
    /// STAGE.out, .err, .exit; for the tests test_K.* (K = task).
    [[nodiscard]] std::filesystem::path log(SlurmStage stage, std::size_t task, const char* extension) const;
};

/// `text` as one shell word: in single quotes, each ' written '\''.
[[nodiscard]] std::string shell_quote(const std::string& text);

/// The batch script of a stage: runs wiredem with every argument quoted
/// (paths of the server's own choosing; the job's text stays in job.json),
/// then writes its exit status to the stage's .exit file (through a rename),
/// which is how the server knows the outcome once Slurm has forgotten the job.
[[nodiscard]] std::string slurm_batch_script(
    SlurmStage stage, const std::string& job_id, const SlurmFiles& files, const SlurmOptions& options,
    double checkpoint_interval_s);

/// sbatch's arguments (without the program) for a stage: --parsable, the
/// job's name, folder, logs, CPUs, the options, the dependency (`after`, 0:
/// none) and for the tests --array=0-(tests-1); the script last.
[[nodiscard]] std::vector<std::string> sbatch_arguments(SlurmStage stage, const std::string& job_id,
    const SlurmFiles& files, const SlurmOptions& options, std::int64_t after, std::size_t tests);

/// The Slurm job name of a job's three Slurm jobs (to find them by name).
[[nodiscard]] std::string slurm_job_name(const std::string& job_id);

/// The id in sbatch --parsable's answer ("123" or "123;cluster"); nothing when
/// it holds none.
[[nodiscard]] std::optional<std::int64_t> parse_sbatch_id(const std::string& out);

/// The squeue format the parser below reads.
inline constexpr const char* squeue_format = "%i|%F|%K|%T|%r";

/// One line of squeue or sacct: a job or an array task.
struct SlurmJobLine {
    std::int64_t job = 0;                  ///< the job's id, or its array's (%F)
    std::optional<std::size_t> task;       ///< the array task (%K), if one
    std::string state;                     ///< PENDING, RUNNING, COMPLETED, FAILED, …
    std::string reason;                    ///< why pending or ended (None, Dependency, NonZeroExitCode, …)
};

/// Parses squeue's output in squeue_format (--noheader --array); lines that
/// do not parse are skipped (a pending array's [0-3] range among them).
[[nodiscard]] std::vector<SlurmJobLine> parse_squeue(const std::string& out);

/// The sacct arguments (without the program) that list `ids` in the form
/// parse_sacct reads: allocations only, '|'-separated.
[[nodiscard]] std::vector<std::string> sacct_arguments(const SlurmIds& ids);

/// Parses `sacct --noheader --parsable2 --format=JobID,State`: "12|COMPLETED",
/// "13_1|FAILED", "13_[2-3]|PENDING".
[[nodiscard]] std::vector<SlurmJobLine> parse_sacct(const std::string& out);

/// Where one stage (or test) of a job stands.
struct SlurmUnit {
    enum class State { unknown, active, succeeded, failed } state = State::unknown;
    std::string slurm_state;               ///< Slurm's word (or "exit N" from the marker)
    std::string reason;                    ///< Slurm's reason
    std::optional<int> exit_code;          ///< from the .exit marker
};

/// A Slurm state word as a unit state: PENDING/RUNNING/… active,
/// COMPLETED succeeded, FAILED/CANCELLED/TIMEOUT/… failed.
[[nodiscard]] SlurmUnit::State slurm_state_kind(const std::string& state);

/// The units of a job: prepare, test 0 … test n-1, analyse, from what
/// squeue says of the job's ids and, for units it does not list (Slurm
/// forgot them: MinJobAge), from their exit markers (`exit_codes`, by
/// index in the same order).
[[nodiscard]] std::vector<SlurmUnit> slurm_units(const SlurmIds& ids, std::size_t tests,
    const std::vector<SlurmJobLine>& lines, const std::vector<std::optional<int>>& exit_codes);

/// What a job's units say.
struct SlurmVerdict {
    enum class Kind {
        running,     ///< some unit is pending or running
        succeeded,   ///< the analysis succeeded
        failed,      ///< a unit failed: `unit` says which
        lost,        ///< nothing pending or running, and not done: Slurm lost the jobs
    } kind = Kind::running;
    std::size_t unit = 0;                  ///< the failed unit's index
};

[[nodiscard]] SlurmVerdict slurm_verdict(const std::vector<SlurmUnit>& units);

/// "preparation", "test 2 of 4", "analysis": unit `k` of a job with `tests` tests.
[[nodiscard]] std::string slurm_unit_name(std::size_t k, std::size_t tests);

} // namespace wiredem::server
