// A job as the server stores and reports it: the record kept in SQLite and the
// states it moves through. Plain data, no I/O.
//
// State machine (a job only ever moves forward, except the requeue arrows):
//   queued → preparing → running → succeeded | failed
//   queued | preparing | running → cancelled         (DELETE /v1/jobs/{id})
//   preparing | running → queued                      (restart after a crash, graceful shutdown)
//   succeeded | failed | cancelled → (removed)        (DELETE /v1/jobs/{id}, --max-finished-jobs)
#pragma once

#include "api/job_spec.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>
#include <string_view>

namespace wiredem::server {

/// Where a job is in its life. `preparing`: a worker has claimed it and the
/// runner is building the specimen; `running`: the runner reports a later stage.
enum class JobState { queued, preparing, running, succeeded, failed, cancelled };

/// All states, in life-cycle order (for metrics and validation).
inline constexpr JobState all_job_states[] = {JobState::queued, JobState::preparing,
    JobState::running, JobState::succeeded, JobState::failed, JobState::cancelled};

/// The lower-case name used in the API and the database.
[[nodiscard]] std::string_view to_string(JobState s) noexcept;

/// Inverse of to_string; nullopt for an unknown name.
[[nodiscard]] std::optional<JobState> job_state_from_string(std::string_view name) noexcept;

/// True for succeeded, failed and cancelled: the job will not change again.
[[nodiscard]] inline bool is_final(JobState s) noexcept
{
    return s == JobState::succeeded || s == JobState::failed || s == JobState::cancelled;
}

/// One row of the job table.
struct JobRecord {
    std::int64_t seq = 0;                  ///< insertion order; the queue is FIFO by seq
    std::string id;                        ///< 24 lower-case hex digits, random
    JobState state = JobState::queued;
    std::string stage;                     ///< last stage reported by the runner
    double progress = 0.0;                 ///< of the current attempt, 0..1
    std::optional<double> eta_s;           ///< runner's estimate of the time left [s]
    std::string message;                   ///< runner's last progress message
    std::string error;                     ///< why it failed (one line), else empty
    int attempts = 0;                      ///< how many times a worker has claimed it
    std::int64_t created_ms = 0;           ///< Unix time [ms]
    std::optional<std::int64_t> started_ms;  ///< start of the latest attempt [ms]
    std::optional<std::int64_t> finished_ms; ///< when it reached a final state [ms]
    std::string name;                      ///< the spec's name (a column of its own: lists never read the spec)
    std::string spec_json;                 ///< the normalised job spec (api::to_json); empty in lists
    std::string idempotency_key;           ///< empty when the client sent none
    std::optional<double> body_steps_per_second; ///< from the summary, once succeeded
};

/// The spec a job was accepted with: spec_json (api::to_json when accepted,
/// perhaps by an older wiredem), read as wiredem wrote it
/// (api::parse_written_job_spec: a field it did not have yet is read as it
/// ran then). Throws std::runtime_error when it does not parse: the store
/// holds only specs it validated.
[[nodiscard]] api::JobSpec stored_spec(const std::string& spec_json);

/// A parameter study (api/study.hpp): its document and its jobs, one per point.
struct StudyRecord {
    std::int64_t seq = 0;                  ///< insertion order
    std::string id;                        ///< 24 lower-case hex digits, like a job's
    std::string name;
    std::int64_t created_ms = 0;           ///< Unix time [ms]
    std::string document_json;             ///< the study document as submitted (parsed and re-serialised)
    std::vector<std::string> job_ids;      ///< the point's job, by point index
};

/// Job counts per state, indexed by JobState.
using StateCounts = std::array<std::int64_t, std::size(all_job_states)>;

/// What a list of studies shows of one: its columns and its jobs counted
/// by state, read without its document or its jobs' specs.
struct StudyListRow {
    std::int64_t seq = 0;
    std::string id;
    std::string name;
    std::int64_t created_ms = 0;
    std::size_t points = 0;
    StateCounts jobs_by_state{};
};

/// The Slurm jobs that run a job under `wiredem-server --executor slurm`
/// (server/slurm.hpp): its preparation, the array of its tests (task K runs
/// test K) and its analysis, each after the one before (afterok).
struct SlurmIds {
    std::int64_t prepare = 0;
    std::int64_t tests = 0;               ///< the array job's id
    std::int64_t analyse = 0;
    std::int64_t submitted_ms = 0;        ///< Unix time [ms]
};

/// Job ids are 24 lower-case hex digits (96 random bits).
inline constexpr std::size_t job_id_length = 24;

/// True if `id` has the form of a job id. Anything else never reaches the
/// store or the file system (no path can be built from it).
[[nodiscard]] bool is_valid_job_id(std::string_view id) noexcept;

/// A fresh random job id (from std::random_device).
[[nodiscard]] std::string make_job_id();

/// Unix time now [ms].
[[nodiscard]] std::int64_t now_ms() noexcept;

/// RFC 3339 UTC time with milliseconds, e.g. 2026-01-31T12:00:00.123Z.
[[nodiscard]] std::string format_rfc3339(std::int64_t unix_ms);

} // namespace wiredem::server
