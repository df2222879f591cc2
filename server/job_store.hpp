// The durable job table: SQLite in WAL mode, one file in the data directory.
//
// Durability: every call that changes a job commits before it returns, with
// synchronous=FULL, so a job answered with 201 survives kill -9 and power loss.
// Thread safety: all members may be called from any thread; one connection,
// serialised by a mutex (each statement takes microseconds to a few ms).
#pragma once

#include "job.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

struct sqlite3;

namespace wiredem::server {

/// What JobStore::insert did.
enum class InsertOutcome {
    created,              ///< a new queued job
    replayed,             ///< the Idempotency-Key names an earlier job with the same spec
    idempotency_conflict, ///< the key names an earlier job with a different spec
    queue_full,           ///< max_queued jobs are already waiting
};

/// What JobStore::cancel did.
enum class CancelOutcome {
    cancelled,        ///< was queued, preparing or running; now cancelled
    already_cancelled,
    already_final,    ///< succeeded or failed: nothing to cancel
    not_found,
};

/// What JobStore::remove did.
enum class RemoveOutcome {
    removed,    ///< the row is gone (its files are the caller's to remove)
    not_final,  ///< queued, preparing or running: cancel it first
    in_study,   ///< one of a study's points: it goes with its study
    not_found,
};

/// The job table (see the file comment for durability and threading).
class JobStore {
public:
    /// Opens (creating if needed) the database file and its schema.
    /// @throws std::runtime_error with SQLite's message when it cannot.
    explicit JobStore(const std::filesystem::path& db_file);
    ~JobStore();
    JobStore(const JobStore&) = delete;
    JobStore& operator=(const JobStore&) = delete;

    /// Adds a queued job unless the queue holds `max_queued` jobs already, or
    /// returns the earlier job with the same idempotency key. `job` carries id,
    /// spec_json, idempotency_key and created_ms; `out` receives the stored row.
    InsertOutcome insert(const JobRecord& job, std::size_t max_queued, JobRecord& out);

    /// The job with this id, if any.
    [[nodiscard]] std::optional<JobRecord> get(const std::string& id);

    /// Up to `limit` jobs, newest first, with seq < `before_seq` (0: no bound),
    /// optionally only those in `state`; without their spec, idempotency key
    /// and rate (what a list shows, and no more, is read).
    [[nodiscard]] std::vector<JobRecord> list(std::optional<JobState> state,
        std::int64_t before_seq, int limit);

    /// Moves the oldest queued job to `preparing`, counts the attempt, stamps
    /// started_ms and resets progress. nullopt when nothing is queued.
    [[nodiscard]] std::optional<JobRecord> claim_next();

    /// Records progress of an active job; may move preparing → running.
    /// No effect unless the job is preparing or running.
    void update_progress(const std::string& id, JobState state, const std::string& stage,
        double progress, std::optional<double> eta_s, const std::string& message);

    /// Moves an active job (preparing/running) to a final state. Returns false
    /// (and changes nothing) when the job was no longer active, e.g. cancelled.
    bool finish(const std::string& id, JobState final_state, const std::string& error,
        std::optional<double> body_steps_per_second);

    /// Cancels a job that is not final yet.
    CancelOutcome cancel(const std::string& id);

    /// Removes a job that has ended (succeeded, failed, cancelled) and is
    /// not one of a study's points.
    RemoveOutcome remove(const std::string& id);

    /// The retention bound: removes the ended jobs beyond the `keep` most
    /// recently finished. A study's job goes with its whole study, once every
    /// job of the study has ended (a study is kept or removed whole). Returns
    /// the removed jobs' ids (their files are the caller's to remove).
    std::vector<std::string> remove_finished_beyond(std::size_t keep);

    /// Puts an active job back into the queue (graceful shutdown); the
    /// interrupted attempt is not counted. Returns false if it was not active.
    bool requeue(const std::string& id);

    /// Puts an active job back into the queue to be tried again; unlike
    /// requeue, the attempt counts. Returns false if it was not active.
    bool retry(const std::string& id);

    /// At start-up: every job left preparing/running by a crash goes back to
    /// queued. Returns their ids.
    std::vector<std::string> requeue_interrupted();

    /// Ids of all succeeded jobs (start-up check of their files).
    [[nodiscard]] std::vector<std::string> succeeded_ids();

    /// Marks a succeeded job failed (its files are gone).
    void demote_to_failed(const std::string& id, const std::string& error);

    /// Number of jobs in each state.
    [[nodiscard]] StateCounts count_by_state();

    /// body_steps_per_second of the most recently finished job that has one.
    [[nodiscard]] std::optional<double> last_body_steps_per_second();

    /// Adds a study and its jobs (queued, in point order) in one
    /// transaction, unless the queue would then hold more than `max_queued`
    /// jobs (queue_full, nothing added). `jobs` carry id, spec_json and
    /// created_ms; `out` receives the stored study.
    InsertOutcome insert_study(
        const StudyRecord& study, const std::vector<JobRecord>& jobs, std::size_t max_queued, StudyRecord& out);

    /// The study with this id, with its jobs' ids by point.
    [[nodiscard]] std::optional<StudyRecord> get_study(const std::string& id);

    /// Up to `limit` studies, newest first, with seq < `before_seq` (0: no
    /// bound): what a list shows, counted in SQL, without reading a study's
    /// document or its jobs' specs (a document may be large).
    [[nodiscard]] std::vector<StudyListRow> list_studies(std::int64_t before_seq, int limit);

    /// Removes a study whose jobs have all ended, with its jobs; `job_ids`
    /// receives their ids (their files are the caller's to remove).
    /// not_final while one of them has not ended.
    RemoveOutcome remove_study(const std::string& id, std::vector<std::string>& job_ids);

    /// Records the Slurm jobs submitted for a job (replacing earlier ones):
    /// a restarted server follows them instead of submitting again.
    void set_slurm_ids(const std::string& job_id, const SlurmIds& ids);

    /// The Slurm jobs recorded for a job, if any.
    [[nodiscard]] std::optional<SlurmIds> slurm_ids(const std::string& job_id);

    /// Ids of the jobs not ended yet that have Slurm jobs.
    [[nodiscard]] std::vector<std::string> unfinished_with_slurm_ids();

    /// Forgets a job's Slurm jobs (Slurm lost them: the next attempt submits anew).
    void clear_slurm_ids(const std::string& job_id);

private:
    /// requeue (the attempt uncounted) and retry (counted): one statement.
    bool back_to_queue(const std::string& id, bool count_attempt);
    std::mutex mutex_;
    sqlite3* db_ = nullptr;
};

} // namespace wiredem::server
