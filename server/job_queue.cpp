// Worker threads and one attempt of a job: spawn the runner, follow its
// progress lines, then publish its files (rename, fsync) before the store
// says succeeded.
#include "job_queue.hpp"

#include "child_process.hpp"
#include "job_files.hpp"
#include "progress_line.hpp"
#include "slurm_client.hpp"

#include "io/atomic_file.hpp"

#include <boost/json.hpp>
#include <spdlog/spdlog.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

namespace wiredem::server {

std::filesystem::path attempt_output_dir(const std::filesystem::path& data_dir, const std::string& id)
{
    // The work folder's layout is written once, in SlurmFiles (slurm.hpp),
    // whichever executor runs the job.
    return SlurmFiles{data_dir / "jobs" / id / "work"}.out();
}
namespace fs = std::filesystem;
namespace json = boost::json;
using clock_type = std::chrono::steady_clock;

namespace {

/// How often a running job's progress is copied to the store at most.
constexpr auto persist_interval = std::chrono::seconds(2);
/// How often a worker checks cancellation and shutdown while a runner runs.
constexpr auto tick = std::chrono::milliseconds(100);
/// How long a worker waits after a full disk kept it from starting a job.
constexpr auto no_space_pause = std::chrono::seconds(5);

std::optional<std::string> read_small_file(const fs::path& p, std::uintmax_t max_bytes)
{
    std::error_code ec;
    if (!fs::is_regular_file(p, ec) || fs::file_size(p, ec) > max_bytes || ec) return std::nullopt;
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    if (!in) return std::nullopt;
    return ss.str();
}

} // namespace

JobQueue::JobQueue(JobStore& store, QueueConfig config) : store_(store), config_(std::move(config))
{
    config_.concurrent_jobs = std::max(1u, config_.concurrent_jobs);
    config_.threads_per_job = std::max(1u, config_.threads_per_job);
    body_steps_per_second_ = store_.last_body_steps_per_second();
    if (config_.slurm) slurm_ = std::make_unique<SlurmClient>(*config_.slurm);
}

JobQueue::~JobQueue() { stop(); }

void JobQueue::start()
{
    // A runner's descendant that leaves its process group (setsid) and is
    // orphaned comes to the server, which kills it with its runner
    // (child_process.hpp), instead of going to init and outliving the job.
    if (!become_subreaper()) spdlog::warn("cannot become the subreaper of the runners: what they leave behind may outlive them");
    for (const auto& id : store_.requeue_interrupted())
        spdlog::warn("job {}: interrupted by a restart, queued again", id);
    for (const auto& id : store_.succeeded_ids()) {
        const fs::path dir = config_.data_dir / "jobs" / id;
        std::error_code ec;
        if (!fs::is_regular_file(dir / "summary.json", ec) || !fs::is_regular_file(dir / "result.h5", ec)) {
            spdlog::error("job {}: result files missing, marked failed", id);
            store_.demote_to_failed(id, "result files missing at server start");
        }
    }
    sweep_leftovers();
    std::lock_guard lock(mutex_);
    if (started_) return;
    started_ = true;
    for (unsigned i = 0; i < config_.concurrent_jobs; ++i) workers_.emplace_back([this, i] { worker_loop(i); });
}

void JobQueue::sweep_leftovers()
{
    const fs::path jobs = config_.data_dir / "jobs";
    std::error_code ec;
    if (fs::is_symlink(jobs, ec)) return;  // remove_job_dir's rule: never follow one
    std::vector<std::string> ids;
    for (fs::directory_iterator it(jobs, ec), end; !ec && it != end; it.increment(ec))
        if (const std::string id = it->path().filename().string(); is_valid_job_id(id)) ids.push_back(id);
    for (const auto& id : ids) {
        const auto job = store_.get(id);
        if (!job) {
            spdlog::warn("job folder {} names no job (a removal was interrupted): removed", id);
            remove_job_dir(config_.data_dir, id);
            continue;
        }
        const fs::path work = jobs / id / "work";
        if (is_final(job->state) && fs::exists(fs::symlink_status(work, ec))) {
            spdlog::warn("job {}: {}, its work folder left (a clean-up was interrupted): removed", id, to_string(job->state));
            fs::remove_all(work, ec);
        }
    }
}

void JobQueue::notify()
{
    {
        std::lock_guard lock(mutex_);
        ++wake_count_;
    }
    wake_.notify_one();
}

void JobQueue::cancel(const std::string& id)
{
    std::unique_lock lock(mutex_);
    auto it = active_.find(id);
    if (it == active_.end()) {
        lock.unlock();
        // A job waiting for a worker may have Slurm jobs already: submitted
        // before a restart, followed again only once a worker claims it.
        if (slurm_)
            if (const auto ids = store_.slurm_ids(id)) slurm_->cancel({ids->prepare, ids->tests, ids->analyse});
        return;
    }
    it->second.cancel_requested = true;
    if (it->second.child && !it->second.signalled) {
        it->second.child->signal(SIGTERM);
        it->second.signalled = true;
        it->second.signalled_at = clock_type::now();
    }
}

void JobQueue::stop()
{
    {
        std::lock_guard lock(mutex_);
        if (stopping_ && workers_.empty()) return;
        stopping_ = true;
        for (auto& [id, a] : active_) {
            if (a.signalled || !a.child) continue;
            a.child->signal(SIGTERM);
            a.signalled = true;
            a.signalled_at = clock_type::now();
        }
    }
    wake_.notify_all();
    for (auto& t : workers_)
        if (t.joinable()) t.join();
    std::lock_guard lock(mutex_);
    workers_.clear();
}

std::optional<LiveProgress> JobQueue::live(const std::string& id) const
{
    std::lock_guard lock(mutex_);
    auto it = active_.find(id);
    if (it == active_.end()) return std::nullopt;
    return it->second.live;
}

unsigned JobQueue::busy_workers() const
{
    std::lock_guard lock(mutex_);
    return static_cast<unsigned>(active_.size());
}

std::optional<double> JobQueue::body_steps_per_second() const
{
    std::lock_guard lock(mutex_);
    return body_steps_per_second_;
}

void JobQueue::worker_loop(unsigned index)
{
    spdlog::debug("worker {} started", index);
    for (;;) {
        std::uint64_t seen = 0;
        {
            std::lock_guard lock(mutex_);
            if (stopping_) break;
            seen = wake_count_;
        }
        std::optional<JobRecord> job;
        try {
            job = store_.claim_next();
        } catch (const std::exception& e) {
            spdlog::error("worker {}: cannot claim a job: {}", index, e.what());
        }
        if (!job) {
            std::unique_lock lock(mutex_);
            // The timeout also picks up jobs queued by anything that did not notify.
            wake_.wait_for(lock, std::chrono::seconds(2), [&] { return stopping_ || wake_count_ != seen; });
            continue;
        }
        if (job->attempts > config_.max_attempts) {
            spdlog::error("job {}: interrupted {} times, giving up", job->id, job->attempts - 1);
            store_.finish(job->id, JobState::failed,
                "gave up after " + std::to_string(job->attempts - 1) + " interrupted attempts", std::nullopt);
            std::error_code ec;
            fs::remove_all(fs::absolute(config_.data_dir / "jobs" / job->id / "work"), ec);  // its checkpoints
            continue;
        }
        try {
            if (slurm_) run_slurm_job(*job);
            else run_job(*job);
        } catch (const std::exception& e) {
            // Nothing here may stop the worker: fail this job and take the next.
            {
                std::lock_guard lock(mutex_);
                active_.erase(job->id);
            }
            const auto* write = dynamic_cast<const engine::io::WriteError*>(&e);
            try {
                if (write && write->no_space()) {
                    // A full disk passes once space is freed: the job waits in
                    // the queue (the attempt uncounted) and the worker a while,
                    // instead of failing every queued job in turn.
                    spdlog::error("job {}: {}; queued again, next try in {} s", job->id, e.what(), no_space_pause.count());
                    store_.requeue(job->id);
                    std::unique_lock lock(mutex_);
                    wake_.wait_for(lock, no_space_pause, [&] { return stopping_; });
                } else {
                    spdlog::error("job {}: {}", job->id, e.what());
                    store_.finish(job->id, JobState::failed, std::string("server error: ") + e.what(), std::nullopt);
                }
            } catch (const std::exception& again) {
                // The store cannot record it either (its disk is full): the
                // job stays active there, and a restart queues it again
                // (requeue_interrupted).
                spdlog::error("job {}: the job store cannot record what happened: {}", job->id, again.what());
            }
        }
    }
    spdlog::debug("worker {} stopped", index);
}

bool JobQueue::begin_attempt(const JobRecord& job)
{
    const fs::path work = fs::absolute(config_.data_dir / "jobs" / job.id / "work");
    // A work folder left by an earlier attempt (a crash, a shutdown, a
    // SIGKILL) is kept: the stages continue from its specimen, finished
    // tests and checkpoints (campaign/stages.hpp), with the same job.json.
    // No symlink planted in the data directory redirects these writes
    // (job_files.hpp); both executors start from them.
    // The runner gets the spec complete as today's wiredem writes it, so a
    // job accepted by an older server runs as it would have run then.
    const std::string spec_text = json::serialize(api::to_json(stored_spec(job.spec_json))) + "\n";
    make_work_dir(config_.data_dir, job.id);
    write_job_file(config_.data_dir, job.id, "work/job.json", spec_text);
    // Register first, then look at the store: a DELETE that came between the
    // claim and here is seen either in the store or as cancel_requested.
    {
        std::lock_guard lock(mutex_);
        active_[job.id];
    }
    const auto current = store_.get(job.id);
    bool stop_now = false;
    {
        std::lock_guard lock(mutex_);
        stop_now = stopping_ || active_[job.id].cancel_requested || !current || current->state != JobState::preparing;
        if (stop_now) active_.erase(job.id);
    }
    if (stop_now) {
        const bool requeued = current && current->state == JobState::preparing;
        if (requeued) store_.requeue(job.id);  // shutdown before the start: its work folder is kept
        spdlog::info("job {}: not started (cancelled or shutting down)", job.id);
        std::error_code ec;
        if (!requeued) fs::remove_all(work, ec);
        return false;
    }
    return true;
}

void JobQueue::run_job(const JobRecord& job)
{
    const fs::path work = fs::absolute(config_.data_dir / "jobs" / job.id / "work");
    const fs::path out = fs::absolute(attempt_output_dir(config_.data_dir, job.id));
    const std::vector<std::string> argv{config_.runner.string(), "run", (work / "job.json").string(), "-o",
        out.string(), "--threads", std::to_string(config_.threads_per_job), "--progress", "json",
        "--checkpoint-interval", json::serialize(json::value(config_.checkpoint_interval_s))};

    if (!begin_attempt(job)) return;

    auto child = std::make_shared<ChildProcess>(argv, work);
    spdlog::info("job {}: attempt {} started (runner pid {}, {} threads)", job.id, job.attempts, child->pid(),
        config_.threads_per_job);
    {
        std::lock_guard lock(mutex_);
        Active& a = active_[job.id];
        a.child = child;
        if (stopping_ || a.cancel_requested) {  // stop() or cancel() ran while the child started
            child->signal(SIGTERM);
            a.signalled = true;
            a.signalled_at = clock_type::now();
        }
    }

    auto last_persist = clock_type::now();
    const auto started = clock_type::now();
    const int status = child->run_to_exit(
        [&](const std::string& line) { on_progress_line(job.id, line, last_persist); },
        [&] {
            std::lock_guard lock(mutex_);
            Active& a = active_[job.id];
            const auto now = clock_type::now();
            if (!a.signalled && config_.max_job_duration.count() > 0 && now - started > config_.max_job_duration) {
                a.timed_out = true;
                a.signalled = true;
                a.signalled_at = now;
                child->signal(SIGTERM);
            }
            if (a.signalled && now - a.signalled_at > config_.kill_grace) child->signal(SIGKILL);
        },
        tick);

    bool cancelled = false;
    bool stopping = false;
    bool timed_out = false;
    {
        std::lock_guard lock(mutex_);
        cancelled = active_[job.id].cancel_requested;
        timed_out = active_[job.id].timed_out;
        stopping = stopping_;
        active_.erase(job.id);
    }
    finish_attempt(job, status, child->stderr_tail(), cancelled, stopping, timed_out);
}

void JobQueue::on_progress_line(const std::string& id, const std::string& line, clock_type::time_point& last_persist)
{
    const auto parsed = parse_progress_line(line);
    if (!parsed) {
        spdlog::debug("job {}: runner: {}", id, line);  // not a progress line; keep it in the log
        return;
    }
    LiveProgress p;
    bool stage_changed = false;
    {
        std::lock_guard lock(mutex_);
        auto it = active_.find(id);
        if (it == active_.end()) return;
        p = it->second.live;
        apply_progress_line(*parsed, p);
        stage_changed = p.stage != it->second.live.stage;
        if (parsed->body_steps_per_second) body_steps_per_second_ = parsed->body_steps_per_second;
        it->second.live = p;
    }
    const auto now = clock_type::now();
    if (stage_changed || now - last_persist >= persist_interval) {
        store_.update_progress(id, p.state, p.stage, p.progress, p.eta_s, p.message);
        last_persist = now;
    }
}

void JobQueue::finish_attempt(const JobRecord& job, int wait_status, const std::string& stderr_tail,
    bool cancelled, bool stopping, bool timed_out)
{
    const fs::path job_dir = fs::absolute(config_.data_dir / "jobs" / job.id);
    const fs::path work = job_dir / "work";
    std::error_code ec;
    const bool exited_ok = WIFEXITED(wait_status) && WEXITSTATUS(wait_status) == 0;

    if (cancelled) {
        spdlog::info("job {}: cancelled, runner {}", job.id, describe_wait_status(wait_status));
        fs::remove_all(work, ec);
        return;
    }
    if (stopping && !exited_ok) {
        store_.requeue(job.id);
        spdlog::info("job {}: stopped by shutdown, queued again (its work folder is kept to continue from)", job.id);
        return;
    }
    if (timed_out) {
        const std::string reason = "stopped after running longer than this server's limit of "
                                 + std::to_string(config_.max_job_duration.count()) + " s (--max-job-seconds)";
        spdlog::warn("job {}: {}", job.id, reason);
        write_job_file(config_.data_dir, job.id, "runner-stderr.log", stderr_tail);
        store_.finish(job.id, JobState::failed, reason, std::nullopt);
        fs::remove_all(work, ec);
        return;
    }
    // SIGKILL that the server did not send is what the kernel's OOM killer
    // sends: tried once more (the attempt counts, like a crash's), then failed
    // with that said.
    const bool killed = WIFSIGNALED(wait_status) && WTERMSIG(wait_status) == SIGKILL;
    if (killed && job.attempts < config_.attempts_after_sigkill) {
        spdlog::warn("job {}: runner killed by SIGKILL (likely out of memory), attempt {}; trying again", job.id,
            job.attempts);
        store_.retry(job.id);  // from the work folder's checkpoints
        notify();
        return;
    }
    if (!exited_ok) {
        std::string reason = last_line(stderr_tail);
        const std::string how = describe_wait_status(wait_status);
        if (killed)
            reason = "runner killed by SIGKILL in each of " + std::to_string(job.attempts)
                   + " attempts, likely out of memory (the kernel's OOM killer sends SIGKILL): run it with fewer "
                     "bodies, or on a machine with more memory";
        else if (reason.empty()) reason = "runner " + how;
        else if (WIFSIGNALED(wait_status)) reason = "runner " + how + ": " + reason;
        spdlog::warn("job {}: failed, runner {}: {}", job.id, how, reason);
        write_job_file(config_.data_dir, job.id, "runner-stderr.log", stderr_tail);
        store_.finish(job.id, JobState::failed, reason, std::nullopt);
        fs::remove_all(work, ec);
        return;
    }

    publish(job);
}

void JobQueue::publish(const JobRecord& job)
{
    const fs::path job_dir = fs::absolute(config_.data_dir / "jobs" / job.id);
    const fs::path work = job_dir / "work";
    const fs::path out = fs::absolute(attempt_output_dir(config_.data_dir, job.id));
    std::error_code ec;
    // Success only with both files; the summary must be a JSON object.
    const auto summary_text = read_small_file(out / "summary.json", max_summary_bytes);
    boost::system::error_code jec;
    const json::value summary = summary_text ? json::parse(*summary_text, jec) : json::value();
    std::string problem;
    if (!summary_text) problem = "runner exited 0 without a readable summary.json";
    else if (jec || !summary.is_object()) problem = "runner wrote a summary.json that is not a JSON object";
    else if (!fs::is_regular_file(out / "result.h5", ec)) problem = "runner exited 0 without result.h5";
    if (!problem.empty()) {
        spdlog::warn("job {}: failed: {}", job.id, problem);
        store_.finish(job.id, JobState::failed, problem, std::nullopt);
        fs::remove_all(work, ec);
        return;
    }
    engine::io::sync_path(out / "result.h5");
    engine::io::sync_path(out / "summary.json");
    fs::rename(out / "result.h5", job_dir / "result.h5");
    // result.xdmf (ParaView's view of result.h5, optional: older runners wrote
    // none) is kept beside it, before the summary that marks success.
    if (fs::is_regular_file(out / "result.xdmf", ec)) {
        engine::io::sync_path(out / "result.xdmf");
        fs::rename(out / "result.xdmf", job_dir / "result.xdmf");
    }
    fs::rename(out / "summary.json", job_dir / "summary.json");
    engine::io::sync_path(job_dir);  // the renames are durable before the store says succeeded
    const auto bsps = number_at(summary, {"engine", "body_steps_per_second"});
    if (store_.finish(job.id, JobState::succeeded, "", bsps)) {
        spdlog::info("job {}: succeeded", job.id);
        if (bsps) {
            std::lock_guard lock(mutex_);
            body_steps_per_second_ = bsps;
        }
    } else {
        spdlog::info("job {}: finished after it was cancelled; kept as cancelled", job.id);
    }
    fs::remove_all(work, ec);
}

} // namespace wiredem::server
