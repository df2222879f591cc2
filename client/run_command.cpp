// The stage commands: `wiredem run`, `prepare`, `test`, `analyse` (docs/api.md,
// "the runner contract"; the stages themselves are campaign/stages.hpp).
// Here: progress display, signals, exit codes.
//
// Progress: fraction 0–1 of the stage (of the whole campaign for `run`), at
// most every half second, with the time left (campaign/eta.hpp). SIGTERM and
// SIGINT set a flag that the engine checks every step (exit 128 + signal); a
// preparation or test killed in any way continues from its last checkpoint
// when started again.
#include "run_command.hpp"

#include "api/json_text.hpp"
#include "api/progress_line.hpp"
#include "core/format.hpp"
#include "display.hpp"
#include "stages.hpp"
#include "study_run.hpp"

#include <boost/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <unistd.h>

namespace json = boost::json;
namespace api = wiredem::api;
namespace campaign = wiredem::campaign;

namespace {

std::atomic<bool> g_cancel{false};
std::atomic<int> g_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

extern "C" void on_stop_signal(int sig)
{
    g_signal.store(sig);
    g_cancel.store(true);
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Progress reports: JSON lines on stdout, or a plain line on stderr (a
/// redrawn bar on a TTY).
class Progress {
public:
    explicit Progress(bool json_lines) : json_(json_lines), tty_(!json_lines && ::isatty(2)), start_(Clock::now()) {}

    /// The campaign's work (`run` reports it before each progress call).
    void work(const campaign::WorkSteps& w)
    {
        has_work_ = true;
        eta_ = eta_from_work_.update(seconds_since(start_), w);
    }

    /// Reports `fraction` of the whole run; throttled unless `force`.
    void report(const char* stage, double fraction, const std::string& message, bool force = false)
    {
        fraction = std::clamp(fraction, 0.0, 1.0);
        // A single stage reports no work: its fraction is its work (a test's
        // steps, a pour's steps up to its limit), measured from its first
        // step report — a test resumed from a checkpoint starts there.
        if (!has_work_ && fraction > 0.0)
            eta_ = eta_from_fraction_.update(seconds_since(start_), campaign::WorkSteps{fraction, 1.0 - fraction, false});
        const auto now = Clock::now();
        if (!force && now - last_ < std::chrono::milliseconds(500)) return;
        last_ = now;
        // The plain lines name the stage, then the message: one that starts
        // with the stage's word ("preparing the specimen") is not preceded
        // by it again ("preparing   0.0% preparing the specimen").
        const bool says_stage = message.rfind(stage, 0) == 0;
        const bool has_eta = fraction < 1.0 && eta_.has_value();
        std::string eta_text;  // appended: GCC 12's -Wrestrict misfires on "literal" + std::string
        if (has_eta) {
            eta_text = " (eta ";
            eta_text += std::to_string(static_cast<long>(*eta_));
            eta_text += " s)";
        }
        if (json_) {
            json::object o;
            namespace key = wiredem::api::progress_line;  // the runner contract's keys, one list
            o[key::stage] = stage;
            o[key::progress] = fraction;
            o[key::eta_s] = nullptr;
            if (has_eta) o[key::eta_s] = *eta_;
            o[key::message] = message;
            std::cout << wiredem::api::json_document_text(o) << '\n' << std::flush;
        } else if (tty_) {
            constexpr int width = 30;
            const int filled = static_cast<int>(fraction * width);
            std::string bar(static_cast<std::size_t>(filled), '#');
            bar.resize(width, '.');
            std::fprintf(stderr, "\r[%s] %5.1f%% %s%s\033[K", bar.c_str(), 100.0 * fraction,
                (says_stage ? message : std::string(stage) + " " + message).c_str(), eta_text.c_str());
            std::fflush(stderr);
            dirty_ = true;
        } else {
            if (says_stage) std::fprintf(stderr, "%5.1f%% %s%s\n", 100.0 * fraction, message.c_str(), eta_text.c_str());
            else std::fprintf(stderr, "%s %5.1f%% %s%s\n", stage, 100.0 * fraction, message.c_str(), eta_text.c_str());
        }
    }

    /// Ends a redrawn bar line before other output.
    void finish_line()
    {
        if (dirty_) std::fputc('\n', stderr);
        dirty_ = false;
    }

private:
    bool json_;
    bool tty_;
    bool dirty_ = false;
    Clock::time_point start_;
    Clock::time_point last_{};
    bool has_work_ = false;
    campaign::EtaEstimate eta_from_work_;
    campaign::EtaEstimate eta_from_fraction_;
    std::optional<double> eta_;  ///< the latest estimate [s]
};

/// Restores the previous signal handlers when the run ends.
class SignalGuard {
public:
    SignalGuard()
    {
        g_cancel.store(false);
        g_signal.store(0);
        struct sigaction sa {};
        sa.sa_handler = on_stop_signal;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGTERM, &sa, &old_term_);
        sigaction(SIGINT, &sa, &old_int_);
    }
    ~SignalGuard()
    {
        sigaction(SIGTERM, &old_term_, nullptr);
        sigaction(SIGINT, &old_int_, nullptr);
    }
    SignalGuard(const SignalGuard&) = delete;
    SignalGuard& operator=(const SignalGuard&) = delete;

private:
    struct sigaction old_term_ {};
    struct sigaction old_int_ {};
};

int fail(Progress& progress, const std::string& reason)
{
    progress.finish_line();
    if (g_cancel.load()) {
        const int sig = g_signal.load();
        std::cerr << "stopped by signal " << sig << '\n';
        return 128 + (sig ? sig : SIGTERM);
    }
    std::cerr << "wiredem: " << reason << '\n';
    return 1;
}

/// Runs one stage with progress, signals and the exit code of the contract.
int run_stage(bool json_progress, campaign::StageControl control,
    const std::function<campaign::StageError(const campaign::StageControl&)>& stage)
{
    SignalGuard guard;
    Progress progress(json_progress);
    const auto t_start = Clock::now();
    control.cancel = &g_cancel;
    control.progress = [&](const char* name, double fraction, const std::string& message) {
        progress.report(name, fraction, message);
    };
    control.work = [&](const campaign::WorkSteps& w) { progress.work(w); };
    try {
        if (auto e = stage(control)) return fail(progress, *e);
    } catch (const std::exception& ex) {
        return fail(progress, ex.what());
    }
    if (g_cancel.load()) return fail(progress, "cancelled");
    // This run's time: a directory continued from an earlier run's files
    // took that run's time too, which this process did not see.
    progress.report(wiredem::api::progress_line::writing, 1.0, "done: this run took " + wiredem::engine::fixed_number(seconds_since(t_start), 1) + " s", true);
    progress.finish_line();
    return 0;
}

} // namespace

int run_campaign_main(const api::JobSpec& spec, const std::filesystem::path& out_dir, const StageOptions& options)
{
    return run_stage(options.json_progress, options.control(), [&](const campaign::StageControl& c) {
        return campaign::run(spec, campaign::JobDir{out_dir}, c);
    });
}

int prepare_main(const api::JobSpec& spec, const std::filesystem::path& out_dir, const StageOptions& options)
{
    return run_stage(options.json_progress, options.control(), [&](const campaign::StageControl& c) {
        return campaign::prepare(spec, campaign::JobDir{out_dir}, c);
    });
}

int test_main(const std::filesystem::path& dir, std::optional<std::size_t> index, std::optional<double> pressure_pa,
    const StageOptions& options)
{
    return run_stage(options.json_progress, options.control(), [&](const campaign::StageControl& c) -> campaign::StageError {
        const campaign::JobDir job_dir{dir};
        std::size_t k = index.value_or(0);
        if (pressure_pa) {
            auto job = campaign::read_job(job_dir);
            if (!job.ok()) return job.error();
            const std::vector<double>& p = job.value().triaxial.confining_pressures_pa;
            const auto it = std::find(p.begin(), p.end(), *pressure_pa);
            if (it == p.end()) {
                std::string list;
                for (double x : p) list += (list.empty() ? "" : ", ") + json::serialize(json::value(x));
                return "--pressure " + json::serialize(json::value(*pressure_pa))
                     + " Pa is not one of the job's confining pressures (" + list + " Pa)";
            }
            k = static_cast<std::size_t>(it - p.begin());
        }
        return campaign::run_test(job_dir, k, c);
    });
}

int free_standing_test_main(const std::filesystem::path& dir, const StageOptions& options)
{
    return run_stage(options.json_progress, options.control(), [&](const campaign::StageControl& c) -> campaign::StageError {
        const campaign::JobDir job_dir{dir};
        auto job = campaign::read_job(job_dir);
        if (!job.ok()) return job.error();
        if (!job.value().free_standing.enabled)
            return "--free-standing: the job has no free-standing test (its free_standing.enabled is false)";
        return campaign::run_free_standing_test(job_dir, c);
    });
}

int analyse_main(const std::filesystem::path& dir, const StageOptions& options)
{
    // The free-standing test (when the job has one and it has not run) comes
    // first: it needs every thread, after the triaxial tests, as in `wiredem
    // run`; a cluster's analysis job runs it (docs/studies.md).
    return run_stage(options.json_progress, options.control(), [&](const campaign::StageControl& c) -> campaign::StageError {
        if (auto e = campaign::run_free_standing_test(campaign::JobDir{dir}, c)) return e;
        return campaign::analyse(campaign::JobDir{dir}, c);
    });
}

int study_run_main(const wiredem::api::Study& study, const std::filesystem::path& dir, std::size_t at_once,
    const StageOptions& options)
{
    SignalGuard guard;
    campaign::StageControl control = options.control();
    control.cancel = &g_cancel;
    const auto t0 = Clock::now();
    const std::size_t n = study.points.size();
    // One line per event: the points take minutes to hours each.
    const auto event = [&](std::size_t k, const std::string& what, const std::string& detail) {
        std::cerr << "study: point " << k + 1 << "/" << n << " (" << wiredem::client::printable(study.points[k].label)
                  << ") " << what << (detail.empty() ? "" : ": " + wiredem::client::printable(detail)) << " at "
                  << static_cast<long>(seconds_since(t0)) << " s\n";
    };
    std::vector<wiredem::api::PointOutcome> outcomes;
    try {
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec) throw std::runtime_error("cannot create " + dir.string() + ": " + ec.message());
        outcomes = campaign::run_study(study, dir, at_once, control, event);
    } catch (const std::exception& e) {
        std::cerr << "wiredem: " << e.what() << '\n';
        return 1;
    }
    const boost::json::value summary = wiredem::api::study_summary(study, outcomes);
    if (options.json_progress)
        std::cout << wiredem::api::json_document_text(summary) << '\n';
    else
        std::cout << wiredem::client::format_study_summary(summary) << "\nfiles: " << (dir / "summary.json").string()
                  << ", " << (dir / "summary.csv").string() << '\n';
    if (g_cancel.load()) {
        const int sig = g_signal.load();
        std::cerr << "stopped by signal " << sig << '\n';
        return 128 + (sig ? sig : SIGTERM);
    }
    const auto failed = std::count_if(outcomes.begin(), outcomes.end(), [](const auto& o) { return o.state != "succeeded"; });
    if (failed > 0) {
        std::cerr << "wiredem: " << failed << " of " << n << " points failed (see their errors above)\n";
        return 1;
    }
    return 0;
}
