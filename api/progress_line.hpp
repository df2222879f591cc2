// The runner's progress line (docs/api.md, "The runner contract"): one JSON
// object per line on the runner's stdout. Its keys and its stages have their
// one home here: `wiredem run --progress json` writes them
// (client/run_command.cpp; the stages' reports, campaign/stages.cpp), the
// server reads them (server/progress_line.cpp; the Slurm executor reports the
// same stages, server/slurm_executor.cpp), and docs/api.md's contract is
// tested against them (tests/server/test_progress_line.cpp).
#pragma once

#include <array>
#include <string_view>

namespace wiredem::api::progress_line {

/// The keys of a line.
inline constexpr const char* stage = "stage";          ///< the stage's name, one of `stages`
inline constexpr const char* progress = "progress";    ///< fraction of the run done, 0–1
inline constexpr const char* eta_s = "eta_s";          ///< time left [s], or null: no estimate
inline constexpr const char* message = "message";      ///< what the stage is doing, text
/// Optional: the engine's throughput [body-steps/s] (the server's metric).
inline constexpr const char* body_steps_per_second = "body_steps_per_second";
inline constexpr std::array<std::string_view, 5> keys{stage, progress, eta_s, message, body_steps_per_second};

/// The stages, in the order a run goes through them. A job is `preparing`
/// until its runner reports another stage, then `running`.
inline constexpr const char* preparing = "preparing";
inline constexpr const char* testing = "testing";
inline constexpr const char* analysing = "analysing";
inline constexpr const char* writing = "writing";
inline constexpr std::array<std::string_view, 4> stages{preparing, testing, analysing, writing};

} // namespace wiredem::api::progress_line
