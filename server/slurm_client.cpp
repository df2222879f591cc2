// Slurm's commands: see slurm_client.hpp.
#include "slurm_client.hpp"

#include "child_process.hpp"

#include <spdlog/spdlog.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <set>

namespace wiredem::server {
namespace fs = std::filesystem;

namespace {

/// Limit of one Slurm command: the controller answers in milliseconds, or
/// is busy or down (then the next poll tries again).
constexpr std::chrono::seconds command_limit{60};

std::string one_line(std::string text)
{
    for (char& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text;
}

} // namespace

bool CommandResult::ok() const { return WIFEXITED(status) && WEXITSTATUS(status) == 0; }

CommandResult run_command(const std::vector<std::string>& argv, std::chrono::seconds limit)
{
    ChildProcess child(argv, "/");
    CommandResult r;
    const auto started = std::chrono::steady_clock::now();
    bool killed = false;
    r.status = child.run_to_exit([&](const std::string& line) { r.out += line + "\n"; },
        [&] {
            if (!killed && std::chrono::steady_clock::now() - started > limit) {
                child.signal(SIGKILL);
                killed = true;
            }
        },
        std::chrono::milliseconds(50));
    r.err = child.stderr_tail();
    if (killed) r.err += "\n(killed after " + std::to_string(limit.count()) + " s)";
    return r;
}

fs::path find_on_path(const std::string& name)
{
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/bin:/bin";
    std::size_t start = 0;
    while (start <= dirs.size()) {
        const std::size_t colon = std::min(dirs.find(':', start), dirs.size());
        const fs::path candidate = fs::path(dirs.substr(start, colon - start)) / name;
        if (candidate.is_absolute() && ::access(candidate.c_str(), X_OK) == 0) return candidate;
        start = colon + 1;
    }
    return {};
}

SlurmClient::SlurmClient(SlurmOptions options) : options_(std::move(options))
{
    for (auto [name, path] : {std::pair{"sbatch", &sbatch_}, {"squeue", &squeue_}, {"scancel", &scancel_}}) {
        *path = find_on_path(name);
        if (path->empty())
            throw std::runtime_error(std::string("--executor slurm: ") + name
                                     + " is not on PATH (install Slurm's client commands, e.g. Debian's slurm-client)");
    }
    sacct_ = find_on_path("sacct");  // optional: only with an accounting database it knows more than squeue
    // The controller must answer now: a server started without one failed
    // its first job, much later, with squeue's error (a DNS failure).
    const CommandResult r = run_command(
        {squeue_.string(), "--noheader", "--name=wiredem-controller-check", "--format=%i"}, command_limit);
    if (!r.ok())
        throw std::runtime_error("--executor slurm: the Slurm controller does not answer (squeue "
                                 + describe_wait_status(r.status) + "): " + one_line(r.err.empty() ? r.out : r.err));
}

SlurmIds SlurmClient::submit(const std::string& job_id, const SlurmFiles& files, std::size_t tests,
    double checkpoint_interval_s)
{
    if (tests == 0) throw std::runtime_error("a job without tests cannot run on Slurm");
    fs::create_directories(files.dir());
    std::vector<std::int64_t> submitted;
    const auto sbatch = [&](SlurmStage stage, std::int64_t after) {
        const fs::path script = files.script(stage);
        {
            std::ofstream f(script, std::ios::binary | std::ios::trunc);
            f << slurm_batch_script(stage, job_id, files, options_, checkpoint_interval_s);
            if (!f) throw std::runtime_error("cannot write " + script.string());
        }
        fs::permissions(script, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec);
        std::vector<std::string> argv{sbatch_.string()};
        for (std::string& a : sbatch_arguments(stage, job_id, files, options_, after, tests)) argv.push_back(std::move(a));
        const CommandResult r = run_command(argv, command_limit);
        const auto id = r.ok() ? parse_sbatch_id(r.out) : std::nullopt;
        if (!id) {
            cancel(submitted);
            throw std::runtime_error("sbatch failed (" + describe_wait_status(r.status) + "): "
                                     + one_line(r.err.empty() ? r.out : r.err));
        }
        submitted.push_back(*id);
        return *id;
    };
    SlurmIds ids;
    ids.prepare = sbatch(SlurmStage::prepare, 0);
    ids.tests = sbatch(SlurmStage::test, ids.prepare);
    ids.analyse = sbatch(SlurmStage::analyse, ids.tests);
    ids.submitted_ms = now_ms();
    return ids;
}

std::vector<SlurmJobLine> SlurmClient::query(const std::string& job_id, const SlurmIds& ids)
{
    // By name, not by id: squeue fails on a list of ids it has all forgotten.
    const CommandResult r = run_command({squeue_.string(), "--noheader", "--array", "--states=all",
                                            "--name=" + slurm_job_name(job_id), "--format=" + std::string(squeue_format)},
        command_limit);
    if (!r.ok()) throw std::runtime_error("squeue failed (" + describe_wait_status(r.status) + "): " + one_line(r.err));
    std::vector<SlurmJobLine> lines = parse_squeue(r.out);
    std::set<std::int64_t> listed;
    for (const SlurmJobLine& l : lines) listed.insert(l.job);
    const bool all_listed = listed.count(ids.prepare) && listed.count(ids.tests) && listed.count(ids.analyse);
    if (!all_listed && !sacct_.empty()) {
        std::vector<std::string> argv{sacct_.string()};
        for (std::string& a : sacct_arguments(ids)) argv.push_back(std::move(a));
        // Without an accounting database sacct says so and fails: the exit markers tell then.
        if (const CommandResult a = run_command(argv, command_limit); a.ok())
            for (const SlurmJobLine& l : parse_sacct(a.out))
                if (!listed.count(l.job)) lines.push_back(l);
    }
    return lines;
}

void SlurmClient::cancel(const std::vector<std::int64_t>& slurm_jobs)
{
    if (slurm_jobs.empty()) return;
    std::vector<std::string> argv{scancel_.string()};
    for (std::int64_t id : slurm_jobs) argv.push_back(std::to_string(id));
    try {
        const CommandResult r = run_command(argv, command_limit);
        if (!r.ok()) spdlog::warn("scancel failed ({}): {}", describe_wait_status(r.status), one_line(r.err));
    } catch (const std::exception& e) {
        spdlog::warn("scancel: {}", e.what());
    }
}

void SlurmClient::cancel_strays(const std::string& job_id, const SlurmIds* keep)
{
    const CommandResult r = run_command({squeue_.string(), "--noheader", "--name=" + slurm_job_name(job_id),
                                            "--format=" + std::string(squeue_format)},
        command_limit);
    if (!r.ok()) throw std::runtime_error("squeue failed (" + describe_wait_status(r.status) + "): " + one_line(r.err));
    std::set<std::int64_t> strays;
    for (const SlurmJobLine& l : parse_squeue(r.out)) {
        const bool ours = keep && (l.job == keep->prepare || l.job == keep->tests || l.job == keep->analyse);
        if (!ours && slurm_state_kind(l.state) == SlurmUnit::State::active) strays.insert(l.job);
    }
    if (strays.empty()) return;
    spdlog::warn("job {}: cancelling {} Slurm job(s) of an earlier, unrecorded submission", job_id, strays.size());
    cancel({strays.begin(), strays.end()});
}

} // namespace wiredem::server
