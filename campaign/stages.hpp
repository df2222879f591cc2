// A campaign in stages, each reading and writing files of one job directory
// (files.hpp): prepare → one test per confining pressure → analyse. The
// stages may run in one process (`run`), in several, one after another or at
// once, or on other machines sharing the directory (a cluster's job steps);
// the files they leave are the same bit for bit, and so are result.h5 and
// summary.json.
//
// A preparation or a test writes a checkpoint every `checkpoint_interval_s`
// of wall time; started again after it was killed, it goes on from the last
// one and ends with the specimen or result an uninterrupted one gives
// (engine::PreparationContinuation, engine::TriaxialContinuation,
// engine::FreeStandingContinuation).
// `run` resumes a job directory at every level: a prepared specimen is not
// prepared again, a finished test not run again.
#pragma once

#include "api/job_spec.hpp"
#include "core/result.hpp"
#include "eta.hpp"
#include "files.hpp"
#include "specimen/preparation.hpp"
#include "state/world.hpp"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace wiredem::campaign {

/// The specimen of a prepared directory: the World ready to test and its report.
struct Specimen {
    engine::World world;
    engine::PreparationReport report;
    std::int64_t threads = 0;   ///< the preparation's engine threads
};

/// Reads `dir`'s specimen.h5 (`wiredem prepare`): the World and its
/// preparation report; an error names what is wrong.
[[nodiscard]] engine::Result<Specimen, std::string> read_specimen(const JobDir& dir);

/// Checkpoints of a running preparation or test, by default every few
/// minutes of wall time: a killed stage loses at most that much; a save of
/// the paper's column costs well under a second.
inline constexpr double default_checkpoint_interval_s = 300.0;

/// How long a stage waits for its lock (stage_lock.hpp): long enough for a
/// runner stopped by SIGTERM to save and go, short enough that a stage
/// started twice is refused soon [s].
inline constexpr double default_lock_wait_s = 30.0;

/// How a host controls a stage. All members optional.
struct StageControl {
    unsigned threads = 0;                        ///< engine threads (0: every core)
    const std::atomic<bool>* cancel = nullptr;   ///< set to stop at the next step
    /// Progress of the stage: (stage name, fraction of the stage done 0–1,
    /// message). `run` calls it with the campaign's overall fraction, from
    /// the thread of whichever test moved, one call at a time.
    std::function<void(const char* stage, double fraction, const std::string& message)> progress;
    /// The work done and left in estimated steps (eta.hpp): `run` calls it
    /// just before each progress call, under the same lock.
    std::function<void(const WorkSteps& work)> work;
    double checkpoint_interval_s = default_checkpoint_interval_s; ///< ≤ 0: no checkpoints
    /// How long a stage waits for its lock when another process holds it
    /// (stage_lock.hpp) before it gives up [s].
    double lock_wait_s = default_lock_wait_s;
    /// prepare (and run): a prepared job directory whose specimen to take
    /// instead of pouring one, when its job prepares the same specimen
    /// (same_specimen); empty: pour. A directory prepared already keeps its own.
    std::filesystem::path specimen_from;
};

/// An error message, or nothing when the stage succeeded.
using StageError = std::optional<std::string>;

/// The job of a directory (DIR/job.json). Errors name the file.
[[nodiscard]] engine::Result<api::JobSpec, std::string> read_job(const JobDir& dir);

/// Why two jobs would not prepare the same specimen: the first field (a
/// JSON path) in which their job.json differ, leaving out what only the
/// tests, the name or the thread count read (`triaxial`, `free_standing`, `name`,
/// `comment`, `engine.threads`); nothing when they would. Conservative: any
/// other difference counts, whether or not the preparation reads it.
[[nodiscard]] std::optional<std::string> specimen_difference(const api::JobSpec& a, const api::JobSpec& b);

/// Prepares the specimen of `spec` into `dir` (job.json, specimen.h5), with
/// the time step of the tests set, from its checkpoint if there is one
/// (specimen.checkpoint.h5, removed when the specimen is written). A
/// directory already prepared for the same job is left as it is; one that
/// holds another job is an error. With control.specimen_from, the specimen
/// is that directory's (copied), which must hold the same specimen's job.
[[nodiscard]] StageError prepare(const api::JobSpec& spec, const JobDir& dir, const StageControl& control);

/// Runs test `index` (the index-th confining pressure) of a prepared
/// directory, from its checkpoint if there is one. A test already done is not
/// run again.
[[nodiscard]] StageError run_test(const JobDir& dir, std::size_t index, const StageControl& control);

/// Runs the free-standing test of a prepared directory (job's
/// free_standing.enabled) into tests/free_standing.h5, from its checkpoint
/// (tests/free_standing.checkpoint.h5, removed when the record is written)
/// if there is one, as run_test; nothing when the job has none or it has run.
[[nodiscard]] StageError run_free_standing_test(const JobDir& dir, const StageControl& control);

/// Reads the specimen and every test, fits the envelopes and writes
/// result.h5, result.xdmf and summary.json (summary.json last: its presence
/// marks a finished campaign).
[[nodiscard]] StageError analyse(const JobDir& dir, const StageControl& control);

/// The whole campaign: prepare, the tests not yet done — up to `control.threads`
/// of them at once, the threads shared among them; when none is left to
/// start, the threads of a test that ended go to the running test with the
/// most work left, which continues from its checkpoint on them —, analyse.
[[nodiscard]] StageError run(const api::JobSpec& spec, const JobDir& dir, const StageControl& control);

} // namespace wiredem::campaign
