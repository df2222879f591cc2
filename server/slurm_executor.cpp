// The Slurm executor's attempt of a job (`wiredem-server --executor slurm`,
// server/slurm.hpp): a worker submits the job's three Slurm jobs, or finds
// them in the store after a restart, and follows them until the analysis
// has written the results (then they are published as the local executor's
// are), a stage failed (the job fails with that stage's stderr), the job is
// cancelled (scancel) or the server stops (the Slurm jobs go on; the next
// server follows them).
#include "job_queue.hpp"

#include "api/derived.hpp"
#include "api/job_spec.hpp"
#include "api/progress_line.hpp"
#include "child_process.hpp"
#include "progress_line.hpp"
#include "slurm_client.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <thread>

namespace wiredem::server {
namespace fs = std::filesystem;
using clock_type = std::chrono::steady_clock;

namespace {

/// How often the worker looks at cancellation and shutdown.
constexpr auto tick = std::chrono::milliseconds(100);
/// How long a cancelled job's Slurm jobs get to leave before its work folder goes.
constexpr auto cancel_wait = std::chrono::seconds(30);
/// The tail of a log that is read [bytes].
constexpr std::streamoff tail_bytes = 4096;

std::string file_tail(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    if (!in) return {};
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(std::max<std::streamoff>(0, size - tail_bytes));
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// The newest progress line a stage wrote to its .out file.
std::optional<ProgressLine> last_progress(const fs::path& out_file)
{
    const std::string text = file_tail(out_file);
    std::size_t end = text.size();
    while (end > 0) {
        const std::size_t begin = text.rfind('\n', end - 1);
        const std::size_t from = begin == std::string::npos ? 0 : begin + 1;
        if (auto line = parse_progress_line(std::string_view(text).substr(from, end - from))) return line;
        if (begin == std::string::npos) break;
        end = begin;
    }
    return std::nullopt;
}

/// A stage's exit marker (written by its batch script), if there is one.
std::optional<int> exit_marker(const fs::path& p)
{
    std::ifstream in(p);
    int code = 0;
    if (in >> code) return code;
    return std::nullopt;
}

/// Every unit's exit marker, in slurm_units' order.
std::vector<std::optional<int>> exit_markers(const SlurmFiles& files, std::size_t tests)
{
    std::vector<std::optional<int>> codes{exit_marker(files.log(SlurmStage::prepare, 0, "exit"))};
    for (std::size_t k = 0; k < tests; ++k) codes.push_back(exit_marker(files.log(SlurmStage::test, k, "exit")));
    codes.push_back(exit_marker(files.log(SlurmStage::analyse, 0, "exit")));
    return codes;
}

/// The log files of unit k.
fs::path unit_log(const SlurmFiles& files, std::size_t k, std::size_t tests, const char* extension)
{
    if (k == 0) return files.log(SlurmStage::prepare, 0, extension);
    if (k > tests) return files.log(SlurmStage::analyse, 0, extension);
    return files.log(SlurmStage::test, k - 1, extension);
}

/// The job's progress from its units and what their stages wrote.
LiveProgress slurm_progress(const std::vector<SlurmUnit>& units, const SlurmFiles& files,
    const api::ProgressShares& shares, const SlurmIds& ids)
{
    using S = SlurmUnit::State;
    const std::size_t tests = units.size() - 2;
    std::vector<double> fraction(units.size(), 0.0);
    std::optional<ProgressLine> newest;
    std::size_t running = 0;
    std::size_t done = 0;
    for (std::size_t k = 0; k < units.size(); ++k) {
        if (units[k].state == S::succeeded) fraction[k] = 1.0;
        else if (units[k].slurm_state == "RUNNING") {
            if (auto line = last_progress(unit_log(files, k, tests, "out"))) {
                fraction[k] = line->progress.value_or(0.0);
                newest = line;
            }
        }
        if (k >= 1 && k <= tests) {
            running += units[k].slurm_state == "RUNNING";
            done += units[k].state == S::succeeded;
        }
    }
    LiveProgress p;
    // The analysis unit runs the free-standing test first (`wiredem analyse`): its fraction stands for both.
    p.progress = shares.overall(fraction[0], std::span<const double>(fraction).subspan(1, tests), fraction.back(), fraction.back());
    if (units[0].state != S::succeeded) {
        p.state = JobState::preparing;
        p.stage = api::progress_line::preparing;
        p.message = "Slurm job " + std::to_string(ids.prepare) + " " + units[0].slurm_state;
    } else if (done < tests) {
        p.state = JobState::running;
        p.stage = api::progress_line::testing;
        p.message = "Slurm array " + std::to_string(ids.tests) + ": " + std::to_string(done) + " of "
                  + std::to_string(tests) + " tests done, " + std::to_string(running) + " running";
    } else {
        p.state = JobState::running;
        p.stage = api::progress_line::analysing;
        p.message = "Slurm job " + std::to_string(ids.analyse) + " " + units.back().slurm_state;
    }
    if (newest && newest->message && !newest->message->empty()) p.message += ": " + *newest->message;
    if (p.message.size() > max_message_bytes) p.message.resize(max_message_bytes);  // ASCII but for the stage's own text
    return p;
}

} // namespace

void JobQueue::run_slurm_job(const JobRecord& job)
{
    const fs::path job_dir = fs::absolute(config_.data_dir / "jobs" / job.id);
    const SlurmFiles files{job_dir / "work"};
    const api::JobSpec spec = stored_spec(job.spec_json);
    const std::size_t tests = spec.triaxial.confining_pressures_pa.size();
    const api::ProgressShares shares = api::progress_shares(api::estimated_work(spec));

    if (!begin_attempt(job)) return;
    const auto leave = [&] {
        std::lock_guard lock(mutex_);
        active_.erase(job.id);
    };

    std::optional<SlurmIds> ids = store_.slurm_ids(job.id);
    if (ids) {
        spdlog::info("job {}: following its Slurm jobs {} (prepare), {} (tests), {} (analyse)", job.id, ids->prepare,
            ids->tests, ids->analyse);
    } else {
        // A fresh submission: the work folder keeps what earlier attempts
        // finished (the stages continue from it), but no exit marker or log
        // of theirs may speak for the new Slurm jobs.
        std::error_code ec;
        fs::remove_all(files.dir(), ec);  // job.json and out/ are begin_attempt's
        // An error here (sbatch refused, the controller away) fails the job
        // with its message (worker_loop).
        slurm_->cancel_strays(job.id, nullptr);
        ids = slurm_->submit(job.id, files, tests, config_.checkpoint_interval_s);
        store_.set_slurm_ids(job.id, *ids);
        spdlog::info("job {}: attempt {} submitted to Slurm: {} (prepare), {} (tests 0-{}), {} (analyse)", job.id,
            job.attempts, ids->prepare, ids->tests, tests - 1, ids->analyse);
    }

    // scancel, then wait until no stage writes into the work folder any more.
    const auto cancel_and_wait = [&] {
        slurm_->cancel({ids->prepare, ids->tests, ids->analyse});
        const auto until = clock_type::now() + cancel_wait;
        while (clock_type::now() < until) {
            try {
                const auto units = slurm_units(*ids, tests, slurm_->query(job.id, *ids), {});
                if (std::none_of(units.begin(), units.end(),
                        [](const SlurmUnit& u) { return u.state == SlurmUnit::State::active; }))
                    return;
            } catch (const std::exception&) {
                return;  // the controller is away: nothing to wait for
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(500));
        }
    };

    auto next_poll = clock_type::now();
    auto last_persist = clock_type::now() - std::chrono::hours(1);
    std::string last_stage;
    std::string last_query_error;
    for (;;) {
        bool cancelled = false;
        bool stopping = false;
        {
            std::lock_guard lock(mutex_);
            cancelled = active_[job.id].cancel_requested;
            stopping = stopping_;
        }
        if (cancelled) {
            cancel_and_wait();
            leave();
            spdlog::info("job {}: cancelled, its Slurm jobs too", job.id);
            std::error_code ec;
            fs::remove_all(files.work, ec);
            return;
        }
        if (stopping) {
            leave();
            store_.requeue(job.id);
            spdlog::info("job {}: the server stops; its Slurm jobs go on and the next server follows them", job.id);
            return;
        }
        if (clock_type::now() < next_poll) {
            std::this_thread::sleep_for(tick);
            continue;
        }
        next_poll = clock_type::now() + config_.slurm->poll_interval;

        std::vector<SlurmJobLine> lines;
        try {
            lines = slurm_->query(job.id, *ids);
            last_query_error.clear();
        } catch (const std::exception& e) {
            if (last_query_error != e.what()) spdlog::warn("job {}: {} (trying again)", job.id, e.what());
            last_query_error = e.what();
            continue;
        }
        const auto units = slurm_units(*ids, tests, lines, exit_markers(files, tests));
        const SlurmVerdict verdict = slurm_verdict(units);
        if (verdict.kind == SlurmVerdict::Kind::running) {
            LiveProgress p = slurm_progress(units, files, shares, *ids);
            {
                std::lock_guard lock(mutex_);
                active_[job.id].live = p;
            }
            const auto now = clock_type::now();
            if (p.stage != last_stage || now - last_persist >= std::chrono::seconds(2)) {
                store_.update_progress(job.id, p.state, p.stage, p.progress, p.eta_s, p.message);
                last_persist = now;
                last_stage = p.stage;
            }
            continue;
        }
        leave();
        if (verdict.kind == SlurmVerdict::Kind::succeeded) {
            publish(job);
            return;
        }
        if (verdict.kind == SlurmVerdict::Kind::lost) {
            // Nothing pending or running and no result: the cluster lost the
            // jobs (a controller restarted without its state, a purge). Another
            // attempt submits them again; its stages continue from the files.
            spdlog::warn("job {}: Slurm no longer knows its jobs and they left no result; submitting again", job.id);
            store_.clear_slurm_ids(job.id);
            store_.retry(job.id);
            notify();
            return;
        }
        const SlurmUnit& u = units[verdict.unit];
        const std::string stderr_tail = file_tail(unit_log(files, verdict.unit, tests, "err"));
        std::string slurm_job = std::to_string(verdict.unit == 0 ? ids->prepare
                                                : verdict.unit > tests ? ids->analyse
                                                                       : ids->tests);
        if (verdict.unit >= 1 && verdict.unit <= tests) slurm_job += "_" + std::to_string(verdict.unit - 1);
        std::string reason = slurm_unit_name(verdict.unit, tests) + " (Slurm job " + slurm_job + ") " + u.slurm_state;
        if (!u.reason.empty() && u.reason != "None") reason += " (" + u.reason + ")";
        if (const std::string line = last_line(stderr_tail); !line.empty()) reason += ": " + line;
        spdlog::warn("job {}: failed: {}", job.id, reason);
        cancel_and_wait();  // the other tests, and the stages after
        std::ofstream(job_dir / "runner-stderr.log", std::ios::binary | std::ios::trunc) << stderr_tail;
        store_.finish(job.id, JobState::failed, reason, std::nullopt);
        std::error_code ec;
        fs::remove_all(files.work, ec);
        return;
    }
}

} // namespace wiredem::server
