// The Slurm executor's pure pieces: see slurm.hpp.
#include "slurm.hpp"

#include "core/format.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>

namespace wiredem::server {
namespace fs = std::filesystem;

namespace {

bool all_of_chars(const std::string& s, const char* allowed_punctuation)
{
    return !s.empty() && std::all_of(s.begin(), s.end(), [&](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || std::strchr(allowed_punctuation, c) != nullptr;
    });
}

/// The pieces of `s` between the separators `sep`, in order (an empty `s`
/// is one empty piece): the fields of squeue's and sacct's lines, task lists,
/// the groups of a time limit.
std::vector<std::string_view> split_on(std::string_view s, char sep)
{
    std::vector<std::string_view> pieces;
    for (std::size_t begin = 0;;) {
        const std::size_t end = s.find(sep, begin);
        pieces.push_back(s.substr(begin, end == std::string_view::npos ? std::string_view::npos : end - begin));
        if (end == std::string_view::npos) return pieces;
        begin = end + 1;
    }
}

/// Whether `s` is one to `max_groups` runs of digits joined by ':'.
bool digit_groups(std::string_view s, std::size_t max_groups)
{
    const auto groups = split_on(s, ':');
    return groups.size() <= max_groups && std::all_of(groups.begin(), groups.end(), [](std::string_view g) {
        return !g.empty() && std::all_of(g.begin(), g.end(), [](char c) { return c >= '0' && c <= '9'; });
    });
}

/// sbatch --time: minutes, minutes:seconds, hours:minutes:seconds,
/// days-hours, days-hours:minutes, days-hours:minutes:seconds.
bool is_slurm_time(std::string_view s)
{
    const std::size_t dash = s.find('-');
    if (dash == std::string_view::npos) return digit_groups(s, 3);
    return digit_groups(s.substr(0, dash), 1) && digit_groups(s.substr(dash + 1), 3);
}

template <class T>
std::optional<T> parse_number(std::string_view s)
{
    T v{};
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
    return v;
}

/// sbatch options the executor sets itself, long and short forms: given
/// again they would break the chain of a job's Slurm jobs or its files.
struct ReservedOption {
    const char* long_name;
    const char* short_name;
    const char* instead;  ///< the server option that sets it, or why
};
constexpr ReservedOption reserved_options[] = {
    {"--array", "-a", "set by the executor (one task per test)"},
    {"--dependency", "-d", "set by the executor (afterok between the stages)"},
    {"--kill-on-invalid-dep", nullptr, "set by the executor"},
    {"--output", "-o", "set by the executor (work/slurm/STAGE.out)"},
    {"--error", "-e", "set by the executor (work/slurm/STAGE.err)"},
    {"--chdir", "-D", "set by the executor (the job's work folder)"},
    {"--job-name", "-J", "set by the executor (wiredem-JOBID, to find a job's Slurm jobs)"},
    {"--parsable", nullptr, "set by the executor"},
    {"--wrap", nullptr, "the executor writes the batch scripts"},
    {"--cpus-per-task", "-c", "use --slurm-cpus-per-task"},
    {"--ntasks", "-n", "a stage is one task"},
    {"--partition", "-p", "use --slurm-partition"},
    {"--account", "-A", "use --slurm-account"},
    {"--time", "-t", "use --slurm-time-limit"},
};

std::string escape_filename_pattern(const std::string& path)
{
    // sbatch expands %j, %a, … in --output and --error: a '%' of the path itself is written %%.
    std::string out;
    for (char c : path) {
        out += c;
        if (c == '%') out += '%';
    }
    return out;
}

const char* stage_word(SlurmStage stage)
{
    switch (stage) {
    case SlurmStage::prepare: return "prepare";
    case SlurmStage::test: return "test";
    case SlurmStage::analyse: return "analyse";
    }
    return "?";
}

} // namespace

std::optional<std::string> slurm_options_problem(const SlurmOptions& o)
{
    if (!o.wiredem.is_absolute() || ::access(o.wiredem.c_str(), X_OK) != 0)
        return "--slurm-wiredem " + o.wiredem.string()
             + " is not an executable file here; give the absolute path of the wiredem binary, the same on every node";
    if (!o.partition.empty() && !all_of_chars(o.partition, "_-.,"))
        return "--slurm-partition '" + o.partition
             + "': a partition name is letters, digits, '_', '-' and '.' (several joined by ',')";
    if (!o.account.empty() && !all_of_chars(o.account, "_-."))
        return "--slurm-account '" + o.account + "': an account name is letters, digits, '_', '-' and '.'";
    if (!o.time_limit.empty() && !is_slurm_time(o.time_limit))
        return "--slurm-time-limit '" + o.time_limit
             + "': give minutes, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS (sbatch --time)";
    if (o.cpus_per_task < 1) return "--slurm-cpus-per-task must be at least 1";
    for (const std::string& opt : o.sbatch_options) {
        const std::string shown = "--slurm-sbatch-option '" + opt + "'";
        if (opt.size() < 2 || opt[0] != '-')
            return shown + ": give each sbatch option with its value as one argument, e.g. --slurm-sbatch-option=--qos=high";
        if (opt.find_first_of(std::string("\n\r\0", 3)) != std::string::npos)
            return shown + ": an option cannot hold a line break";
        const std::string name = opt.substr(0, opt.find('='));
        for (const ReservedOption& r : reserved_options) {
            const bool is_long = name == r.long_name;
            const bool is_short = r.short_name && opt[1] != '-' && opt.compare(0, 2, r.short_name) == 0;
            if (is_long || is_short) return shown + ": " + r.long_name + " is " + r.instead;
        }
    }
    if (o.poll_interval.count() <= 0) return "--slurm-poll-seconds must be positive";
    return std::nullopt;
}

fs::path SlurmFiles::script(SlurmStage stage) const { return dir() / (std::string(stage_word(stage)) + ".sh"); }

fs::path SlurmFiles::log(SlurmStage stage, std::size_t task, const char* extension) const
{
    // Appends only: GCC 12 warns (-Wrestrict, a false positive) on "_" + std::string.
    std::string name = stage_word(stage);
    if (stage == SlurmStage::test) name.append("_").append(std::to_string(task));
    name.append(".").append(extension);
    return dir() / name;
}

std::string shell_quote(const std::string& text)
{
    std::string out = "'";
    for (char c : text) {
        if (c == '\'') out += "'\\''";
        else out += c;
    }
    return out + "'";
}

std::string slurm_job_name(const std::string& job_id) { return "wiredem-" + job_id; }

std::string slurm_batch_script(
    SlurmStage stage, const std::string& job_id, const SlurmFiles& files, const SlurmOptions& options,
    double checkpoint_interval_s)
{
    // The task's index comes from Slurm as a shell variable, the rest as quoted words.
    const std::string task = "\"$SLURM_ARRAY_TASK_ID\"";
    std::vector<std::string> words{shell_quote(options.wiredem.string()), shell_quote(stage_word(stage))};
    const auto add = [&](const std::string& w) { words.push_back(shell_quote(w)); };
    if (stage == SlurmStage::prepare) {
        add(files.job_json().string());
        add("-o");
    }
    add(files.out().string());
    if (stage == SlurmStage::test) {
        add("--index");
        words.push_back(task);
    }
    add("--threads");
    add(std::to_string(options.cpus_per_task));
    add("--progress");
    add("json");
    // Every stage keeps checkpoints at the server's interval: the preparation,
    // each test, and the analysis, which runs the free-standing test.
    add("--checkpoint-interval");
    add(engine::exact_number(checkpoint_interval_s));  // shortest exact
    const std::string exit_file = stage == SlurmStage::test
        ? shell_quote((files.dir() / "test_").string()) + task + shell_quote(".exit")
        : shell_quote(files.log(stage, 0, "exit").string());

    std::string script = "#!/bin/sh\n";
    script += "# wiredem-server --executor slurm: ";
    script += stage == SlurmStage::prepare ? "the preparation" : stage == SlurmStage::test ? "a test (the array task's)" : "the analysis";
    script += " of job " + job_id + ".\n";
    script += "# Every word is quoted: the job's own text is in job.json, never here.\n";
    for (std::size_t i = 0; i < words.size(); ++i) script += (i ? " " : "") + words[i];
    script += "\nstatus=$?\n";
    script += "# The exit status outlives Slurm's memory of the job (MinJobAge); written whole, by a rename.\n";
    script += "printf '%s\\n' \"$status\" > " + exit_file + ".part && mv -f " + exit_file + ".part " + exit_file + "\n";
    script += "exit \"$status\"\n";
    return script;
}

std::vector<std::string> sbatch_arguments(SlurmStage stage, const std::string& job_id, const SlurmFiles& files,
    const SlurmOptions& options, std::int64_t after, std::size_t tests)
{
    // The folder's own '%' escaped; the tests' logs named by sbatch's %a (the array task).
    const std::string logs = escape_filename_pattern((files.dir() / "").string())
                           + (stage == SlurmStage::test ? "test_%a" : stage_word(stage));
    std::vector<std::string> args{"--parsable", "--job-name=" + slurm_job_name(job_id),
        "--chdir=" + files.work.string(), "--output=" + logs + ".out", "--error=" + logs + ".err",
        "--ntasks=1", "--cpus-per-task=" + std::to_string(options.cpus_per_task)};
    if (!options.partition.empty()) args.push_back("--partition=" + options.partition);
    if (!options.account.empty()) args.push_back("--account=" + options.account);
    if (!options.time_limit.empty()) args.push_back("--time=" + options.time_limit);
    if (after > 0) {
        args.push_back("--dependency=afterok:" + std::to_string(after));
        // A failed stage cancels those after it, rather than leaving them pending forever.
        args.push_back("--kill-on-invalid-dep=yes");
    }
    if (stage == SlurmStage::test) args.push_back("--array=0-" + std::to_string(tests - 1));
    args.insert(args.end(), options.sbatch_options.begin(), options.sbatch_options.end());
    args.push_back(files.script(stage).string());
    return args;
}

std::optional<std::int64_t> parse_sbatch_id(const std::string& out)
{
    std::string s = out.substr(0, out.find_first_of(";\n"));
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    const auto id = parse_number<std::int64_t>(s);
    if (!id || *id <= 0) return std::nullopt;
    return id;
}

namespace {

/// An array task list as squeue prints it: 3, 0-3, [0-3], 1,4-5, [0-9%2].
std::optional<std::vector<std::size_t>> parse_task_list(std::string_view s)
{
    if (s.size() >= 2 && s.front() == '[' && s.back() == ']') s = s.substr(1, s.size() - 2);
    s = s.substr(0, s.find('%'));  // a throttle, "%2"
    std::vector<std::size_t> tasks;
    for (std::string_view part : split_on(s, ',')) {
        const std::size_t dash = part.find('-');
        const auto a = parse_number<std::size_t>(part.substr(0, dash));
        const auto b = dash == std::string_view::npos ? a : parse_number<std::size_t>(part.substr(dash + 1));
        if (!a || !b || *b < *a || *b - *a > 100000) return std::nullopt;
        for (std::size_t t = *a; t <= *b; ++t) tasks.push_back(t);
    }
    return tasks;
}

/// The lines of one Slurm job as squeue or sacct names it: the job itself
/// without `tasks`, else one per array task the list names (none when it does
/// not parse).
void add_job_lines(std::vector<SlurmJobLine>& lines, std::int64_t job, std::optional<std::string_view> tasks,
    std::string_view state, std::string_view reason)
{
    if (!tasks) {
        lines.push_back({job, std::nullopt, std::string(state), std::string(reason)});
        return;
    }
    if (const auto list = parse_task_list(*tasks))
        for (std::size_t t : *list) lines.push_back({job, t, std::string(state), std::string(reason)});
}

} // namespace

std::vector<SlurmJobLine> parse_squeue(const std::string& out)
{
    std::vector<SlurmJobLine> lines;
    for (std::string_view line : split_on(out, '\n')) {
        const auto f = split_on(line, '|');
        if (f.size() != 5) continue;
        const auto job = parse_number<std::int64_t>(f[1]);
        if (!job || f[3].empty()) continue;
        const bool no_task = f[2] == "N/A" || f[2].empty();
        add_job_lines(lines, *job, no_task ? std::nullopt : std::optional(f[2]), f[3], f[4]);
    }
    return lines;
}

std::vector<std::string> sacct_arguments(const SlurmIds& ids)
{
    return {"--noheader", "--parsable2", "--allocations", "--format=JobID,State",
        "--jobs=" + std::to_string(ids.prepare) + "," + std::to_string(ids.tests) + "," + std::to_string(ids.analyse)};
}

std::vector<SlurmJobLine> parse_sacct(const std::string& out)
{
    std::vector<SlurmJobLine> lines;
    for (std::string_view line : split_on(out, '\n')) {
        const std::size_t bar = line.find('|');
        if (bar == std::string_view::npos) continue;
        const std::string_view id = line.substr(0, bar), state = line.substr(bar + 1);
        const std::size_t underscore = id.find('_');
        const auto job = parse_number<std::int64_t>(id.substr(0, underscore));
        if (!job || state.empty()) continue;
        // "123" is the job; "123_[0-3]" or "123_2" its array's tasks.
        const bool no_task = underscore == std::string_view::npos;
        add_job_lines(lines, *job, no_task ? std::nullopt : std::optional(id.substr(underscore + 1)), state, "");
    }
    return lines;
}

SlurmUnit::State slurm_state_kind(const std::string& state)
{
    using S = SlurmUnit::State;
    static const std::map<std::string, S, std::less<>> kinds{
        {"PENDING", S::active}, {"CONFIGURING", S::active}, {"RUNNING", S::active}, {"COMPLETING", S::active},
        {"SUSPENDED", S::active}, {"REQUEUED", S::active}, {"REQUEUE_HOLD", S::active}, {"REQUEUE_FED", S::active},
        {"RESIZING", S::active}, {"SIGNALING", S::active}, {"STAGE_OUT", S::active}, {"STOPPED", S::active},
        {"RESV_DEL_HOLD", S::active}, {"COMPLETED", S::succeeded}, {"FAILED", S::failed}, {"CANCELLED", S::failed},
        {"TIMEOUT", S::failed}, {"NODE_FAIL", S::failed}, {"OUT_OF_MEMORY", S::failed}, {"PREEMPTED", S::failed},
        {"BOOT_FAIL", S::failed}, {"DEADLINE", S::failed}, {"SPECIAL_EXIT", S::failed}, {"REVOKED", S::failed}};
    // sacct and scontrol may add words ("CANCELLED by 0"): the first one counts.
    const auto it = kinds.find(state.substr(0, state.find(' ')));
    return it == kinds.end() ? S::unknown : it->second;
}

std::vector<SlurmUnit> slurm_units(const SlurmIds& ids, std::size_t tests, const std::vector<SlurmJobLine>& lines,
    const std::vector<std::optional<int>>& exit_codes)
{
    std::vector<SlurmUnit> units(tests + 2);
    std::vector<bool> listed(units.size(), false);
    for (const SlurmJobLine& l : lines) {
        std::size_t k = units.size();
        if (l.job == ids.prepare && !l.task) k = 0;
        else if (l.job == ids.tests && l.task && *l.task < tests) k = 1 + *l.task;
        else if (l.job == ids.analyse && !l.task) k = tests + 1;
        if (k == units.size()) continue;
        units[k].state = slurm_state_kind(l.state);
        units[k].slurm_state = l.state;
        units[k].reason = l.reason;
        listed[k] = true;
    }
    for (std::size_t k = 0; k < units.size(); ++k) {
        if (k < exit_codes.size()) units[k].exit_code = exit_codes[k];
        if (listed[k] || !units[k].exit_code) continue;
        units[k].state = *units[k].exit_code == 0 ? SlurmUnit::State::succeeded : SlurmUnit::State::failed;
        units[k].slurm_state = "exit " + std::to_string(*units[k].exit_code);
    }
    return units;
}

SlurmVerdict slurm_verdict(const std::vector<SlurmUnit>& units)
{
    using S = SlurmUnit::State;
    for (std::size_t k = 0; k < units.size(); ++k)
        if (units[k].state == S::failed) return {SlurmVerdict::Kind::failed, k};
    if (!units.empty() && units.back().state == S::succeeded) return {SlurmVerdict::Kind::succeeded, 0};
    for (const SlurmUnit& u : units)
        if (u.state == S::active) return {SlurmVerdict::Kind::running, 0};
    return {SlurmVerdict::Kind::lost, 0};
}

std::string slurm_unit_name(std::size_t k, std::size_t tests)
{
    if (k == 0) return "preparation";
    if (k > tests) return "analysis";
    return "test " + std::to_string(k) + " of " + std::to_string(tests);
}

} // namespace wiredem::server
