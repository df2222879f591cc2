// `wiredem run`: the local campaign runner, also what wiredem-server's workers
// start for each job (the runner contract, docs/api.md):
//   wiredem run JOB.json -o OUTDIR --threads N --progress json
#pragma once

#include "api/job_spec.hpp"

#include <filesystem>

/// Runs the whole triaxial campaign of `spec`, writing OUTDIR/summary.json and
/// OUTDIR/result.h5 (temp names, then rename). With `json_progress`, prints
/// one JSON progress object per line on stdout; otherwise readable progress.
/// Stops within a second on SIGTERM.
/// @param threads engine threads, ≥ 1
/// @return the process exit code: 0 on success; non-zero with a one-line
///         reason as the last line on stderr; 143 when stopped by SIGTERM
int run_campaign_main(const wiredem::api::JobSpec& spec, const std::filesystem::path& out_dir, unsigned threads,
    bool json_progress);
