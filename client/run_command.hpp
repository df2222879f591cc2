// The stage commands of the command line: `wiredem run` (the whole campaign;
// also what wiredem-server's workers start for each job, the runner contract
// of docs/api.md: wiredem run JOB.json -o OUTDIR --threads N --progress json),
// and its stages `prepare`, `test`, `analyse` (campaign/stages.hpp).
#pragma once

#include "api/job_spec.hpp"
#include "api/study.hpp"
#include "stages.hpp"

#include <cstddef>
#include <filesystem>
#include <optional>

/// Options every stage command takes.
struct StageOptions {
    unsigned threads = 1;          ///< engine threads, ≥ 1
    bool json_progress = false;    ///< one JSON progress object per line on stdout; otherwise readable progress
    double checkpoint_interval_s = wiredem::campaign::default_checkpoint_interval_s; ///< ≤ 0: none
    double lock_wait_s = wiredem::campaign::default_lock_wait_s; ///< for a stage's lock held by another process
    std::filesystem::path specimen_from;  ///< run, prepare: take this prepared directory's specimen (StageControl)

    [[nodiscard]] wiredem::campaign::StageControl control() const
    {
        wiredem::campaign::StageControl c;
        c.threads = threads;
        c.checkpoint_interval_s = checkpoint_interval_s;
        c.lock_wait_s = lock_wait_s;
        c.specimen_from = specimen_from;
        return c;
    }
};

// Each returns the process exit code: 0 on success; non-zero with a one-line
// reason as the last line on stderr; 128 + signal when stopped by SIGTERM or
// SIGINT (within a second).

/// The whole campaign of `spec` in OUTDIR, resuming what is there: writes
/// OUTDIR/summary.json and OUTDIR/result.h5 (temp names, then rename).
int run_campaign_main(const wiredem::api::JobSpec& spec, const std::filesystem::path& out_dir, const StageOptions& options);
/// Prepares the specimen into OUTDIR (job.json, specimen.h5).
int prepare_main(const wiredem::api::JobSpec& spec, const std::filesystem::path& out_dir, const StageOptions& options);
/// Runs one test of a prepared directory, chosen by index or by its confining pressure.
int test_main(const std::filesystem::path& dir, std::optional<std::size_t> index, std::optional<double> pressure_pa,
    const StageOptions& options);
/// Runs the free-standing test of a prepared directory (an error when the job
/// has none); `run` and `analyse` run it after the triaxial tests.
int free_standing_test_main(const std::filesystem::path& dir, const StageOptions& options);
/// Writes result.h5, result.xdmf and summary.json from the tests of a directory.
int analyse_main(const std::filesystem::path& dir, const StageOptions& options);
/// Runs a parameter study here (campaign/study_run.hpp), `at_once` points at a
/// time, and prints its summary (JSON with json_progress); exit 1 when a
/// point failed, its error printed.
int study_run_main(const wiredem::api::Study& study, const std::filesystem::path& dir, std::size_t at_once,
    const StageOptions& options);
