// The subcommands of `wiredem`. Each returns the process exit code
// (exit_codes.hpp) or throws CommandError; output goes to stdout, progress of
// `wait` to stdout as well (a bar on a terminal, plain lines otherwise).
#pragma once

#include "http_client.hpp"
#include "stages.hpp"

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

namespace wiredem::client {

/// Options shared by every command that talks to a server.
struct GlobalOptions {
    std::string server_url;          ///< --server, else WIREDEM_SERVER, else http://127.0.0.1:8080
    std::string token_file;          ///< --token-file, else WIREDEM_TOKEN_FILE; "" for none
    bool json = false;               ///< machine-readable output
    std::chrono::milliseconds timeout{30000};  ///< per network operation
};

/// How `wait` polls.
struct WaitOptions {
    double interval_s = 1.0;              ///< between polls
    std::optional<double> timeout_s;      ///< give up (exit 10) after this
};

/// `submit`: validate locally, POST with a fresh Idempotency-Key (retried on
/// network errors), print the id; with `wait`, then wait like cmd_wait.
int cmd_submit(const GlobalOptions& g, const std::filesystem::path& job_file, bool wait, const WaitOptions& w);
/// `status`: the job as a key/value block (or its JSON).
int cmd_status(const GlobalOptions& g, const std::string& id);
/// `wait`: poll until the job ends; exit code from its final state.
int cmd_wait(const GlobalOptions& g, const std::string& id, const WaitOptions& w);
/// `list`: a page of jobs (every page with `all`), optionally of one state.
int cmd_list(const GlobalOptions& g, const std::string& state, int limit, bool all);
/// `cancel`: DELETE the job.
int cmd_cancel(const GlobalOptions& g, const std::string& id);
/// `summary`: the results table (or the summary JSON).
int cmd_summary(const GlobalOptions& g, const std::string& id);
/// `fetch`: DIR/summary.json and DIR/result.h5, resuming a DIR/result.h5.part.
int cmd_fetch(const GlobalOptions& g, const std::string& id, const std::filesystem::path& dir);
/// `health`: GET /v1/health.
int cmd_health(const GlobalOptions& g);
/// What the local stage commands are asked to do.
struct LocalStage {
    std::filesystem::path job_file;             ///< run, prepare
    std::filesystem::path dir;                  ///< the job directory
    std::optional<std::size_t> index;           ///< test: by index …
    std::optional<double> pressure_pa;          ///< … or by confining pressure
    bool free_standing = false;                 ///< … or the free-standing test
    unsigned threads = 0;                       ///< 0: every core
    std::string progress = "text";              ///< text or json
    double checkpoint_interval_s = campaign::default_checkpoint_interval_s; ///< run, prepare, test; ≤ 0: none
    double lock_wait_s = campaign::default_lock_wait_s; ///< run, prepare, test, analyse
    std::filesystem::path specimen_from;        ///< run, prepare: a prepared directory whose specimen to take
};
/// `wiredem run`: validates the job file, then runs the campaign locally
/// (resuming what the directory holds).
int cmd_run(const LocalStage& s);
/// `wiredem prepare`, `test`, `analyse`: the campaign's stages (campaign/stages.hpp).
int cmd_prepare(const LocalStage& s);
int cmd_test(const LocalStage& s);
int cmd_analyse(const LocalStage& s);
/// `study check`: validates the study and prints its points (label, job name).
int cmd_study_check(const GlobalOptions& g, const std::filesystem::path& study_file, std::size_t max_points);
/// `study submit`: validates the study locally (every point as a job), POSTs
/// it, prints the study id; with `wait`, then waits like cmd_study_wait.
int cmd_study_submit(const GlobalOptions& g, const std::filesystem::path& study_file, bool wait, const WaitOptions& w);
/// `study status`: the study, its jobs counted by state and one line per point.
int cmd_study_status(const GlobalOptions& g, const std::string& id);
/// `study wait`: polls until every job of the study has ended, a line per
/// change of the counts; exit 0 when all succeeded, else the job_failed code.
int cmd_study_wait(const GlobalOptions& g, const std::string& id, const WaitOptions& w);
/// `study cancel`: cancels every job of the study that has not ended.
int cmd_study_cancel(const GlobalOptions& g, const std::string& id);
/// `study delete`: deletes a study whose jobs have all ended, with its jobs
/// and their files (DELETE /v1/studies/{id}?remove=true).
int cmd_study_delete(const GlobalOptions& g, const std::string& id);
/// `study summary`: the table of φ and c over the seeds and per point (or CSV, or JSON).
int cmd_study_summary(const GlobalOptions& g, const std::string& id, bool csv);
/// `study fetch`: DIR/summary.json, DIR/summary.csv and each succeeded
/// point's files into DIR/points/K (like `fetch`, resuming).
int cmd_study_fetch(const GlobalOptions& g, const std::string& id, const std::filesystem::path& dir);
/// `wiredem study run`: validates the study (every point as a job), then runs
/// it locally, `jobs` points at once.
int cmd_study_run(const std::filesystem::path& study_file, const LocalStage& s, std::size_t jobs, std::size_t max_points);

} // namespace wiredem::client
