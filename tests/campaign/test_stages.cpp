// The campaign's stages through the real `wiredem` binary on examples/tiny.json (a short test: tiny_job()):
// prepare + test + analyse give the files `run` gives, bit for bit; tests run
// at once give what tests run one after another give; a test or a preparation
// killed with SIGKILL at several points continues from its checkpoints to the
// same result, a preparation stopped by SIGTERM saves on its way out, a
// free-standing test stopped in every phase continues to the same record;
// and bad requests get clear errors.
#include "api/job_spec.hpp"
#include "h5_compare.hpp"
#include "io/hdf5.hpp"
#include "result_file_names.hpp"
#include "source_tree.hpp"
#include "stages.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <csignal>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <spawn.h>
#include <sstream>
#include <string>
#include <string_view>
#include <sys/file.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <thread>
#include <tuple>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace api = wiredem::api;
namespace campaign = wiredem::campaign;
using wiredem::test::h5_differences;
using wiredem::test_support::read_text;
using wiredem::test_support::source;

namespace fs = std::filesystem;
namespace json = boost::json;

namespace {

/// This process's scratch directory in the temporary directory, made on first
/// use: the job file and every case's directory live in it.
const fs::path& scratch_root()
{
    static const fs::path root = [] {
        const fs::path p = fs::temp_directory_path() / ("wiredem_stages_" + std::to_string(::getpid()));
        fs::remove_all(p);
        fs::create_directories(p);
        return p;
    }();
    return root;
}

/// Removes the scratch directory after the last test when all passed; keeps
/// it, and says where, when one failed (its logs and files are what to look at).
class ScratchCleanup : public ::testing::Environment {
public:
    void TearDown() override
    {
        const fs::path& root = scratch_root();
        if (::testing::UnitTest::GetInstance()->Failed()) {
            std::cerr << "wiredem_stages_tests: a test failed; its files are kept in " << root << '\n';
            return;
        }
        std::error_code ignored;
        fs::remove_all(root, ignored);
    }
};
[[maybe_unused]] const ::testing::Environment* const scratch_cleanup =
    ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

/// examples/tiny.json with a shorter test, written once per process under
/// `name`: loaded to `strain` instead of 8 %, after a ramp and hold of `ramp_s`
/// and `hold_s` instead of 5 and 10 ms.
fs::path tiny_variant(const std::string& name, double strain, double ramp_s, double hold_s)
{
    std::ifstream in(source("examples/tiny.json"));
    std::ostringstream text;
    text << in.rdbuf();
    json::value job = json::parse(text.str());
    json::object& triaxial = job.as_object()["triaxial"].as_object();
    triaxial["target_axial_strain"] = strain;
    triaxial["snapshot_strains"] = json::array{0.0, strain / 2, strain};
    triaxial["pressure_ramp_time_s"] = ramp_s;
    triaxial["hold_time_s"] = hold_s;
    const fs::path p = scratch_root() / name;
    std::ofstream(p) << json::serialize(job);
    return p;
}

/// The campaign these cases run: the stages' orchestration needs a campaign
/// that runs, not a consolidated column or its strength (the runner warns
/// that it had not consolidated). Loaded to 1 % after a ramp of 2 ms and a
/// hold of 3 ms: each test costs 0.4 of the 2 % test after the 10 ms hold
/// (which the consolidation check lengthened to the end of its max_hold_time_s),
/// and 8 % took these cases ~20 min under ASan.
const fs::path& tiny_job()
{
    static const fs::path path = tiny_variant("job.json", 0.01, 0.002, 0.003);
    return path;
}

/// The cases that kill a test after growing delays need a test that lasts
/// long enough to be killed twice after a checkpoint: loaded to 2 % after the
/// example's ramp and hold.
const fs::path& longer_tiny_job()
{
    static const fs::path path = tiny_variant("longer_job.json", 0.02, 0.005, 0.01);
    return path;
}

fs::path fresh_dir(const std::string& name)
{
    const fs::path dir = scratch_root() / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

struct Outcome {
    int status = -1;    ///< wait status
    std::string err;    ///< stderr
    [[nodiscard]] bool ok() const { return WIFEXITED(status) && WEXITSTATUS(status) == 0; }
    [[nodiscard]] int code() const { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }
};

pid_t spawn(const std::vector<std::string>& args, const fs::path& log)
{
    std::vector<const char*> argv{WIREDEM_BIN};
    for (const auto& a : args) argv.push_back(a.c_str());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, WIREDEM_BIN, &fa, nullptr, const_cast<char* const*>(argv.data()), environ);
    posix_spawn_file_actions_destroy(&fa);
    return rc == 0 ? pid : -1;
}

/// Waits (up to a minute) until process `pid` catches `sig` (SigCgt in
/// /proc/PID/status): before that, the signal's default action would kill it,
/// which says nothing about how wiredem stops (a slow start, e.g. under ASan).
/// What wait_until_it_catches saw.
enum class Catching { yes, exited, timed_out };

/// Waits until the process `pid` has a handler for `sig`, or has exited (a
/// zombie, not reaped: the caller's waitpid gives its status). A run that
/// has little left to do (a preparation continued from a checkpoint near its
/// end) may finish and restore the default handlers before a poll sees them.
Catching wait_until_it_catches(pid_t pid, int sig)
{
    const auto until = std::chrono::steady_clock::now() + std::chrono::minutes(1);
    while (std::chrono::steady_clock::now() < until) {
        std::ifstream status("/proc/" + std::to_string(pid) + "/status");
        for (std::string line; std::getline(status, line);) {
            if (line.rfind("State:", 0) == 0 && line.find('Z') != std::string::npos) return Catching::exited;
            if (line.rfind("SigCgt:", 0) == 0 && (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1) & 1u))
                return Catching::yes;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return Catching::timed_out;
}

Outcome run_wiredem(const std::vector<std::string>& args, const fs::path& log)
{
    Outcome o;
    const pid_t pid = spawn(args, log);
    if (pid > 0) waitpid(pid, &o.status, 0);
    o.err = read_text(log);
    return o;
}

/// summary.json without what says how a run went rather than what it computed.
json::value computed(const fs::path& summary)
{
    json::value v = json::parse(read_text(summary));
    for (json::value& t : v.at("tests").as_array()) {
        t.as_object().erase("wall_time_s");
        t.as_object().erase("threads");
    }
    v.at("engine").as_object().erase("wall_time_s");
    v.at("engine").as_object().erase("body_steps_per_second");
    v.at("engine").as_object().erase("threads");
    v.at("specimen").as_object().erase("preparation_wall_time_s");
    return v;
}

const std::set<std::string> how_it_ran{"wall_time_s", "threads"};

std::string joined(const std::vector<std::string>& v)
{
    std::string s;
    for (const auto& x : v) s += x + "\n";
    return s;
}

/// The reference: `wiredem run` of `job` with one thread (tests one after
/// another), computed once per job for the suite.
const fs::path& reference_run(const fs::path& job = tiny_job())
{
    static std::map<fs::path, fs::path> runs;
    if (const auto it = runs.find(job); it != runs.end()) return it->second;
    const fs::path d = fresh_dir("reference_" + job.stem().string());
    const Outcome o = run_wiredem({"run", job.string(), "-o", (d / "out").string(), "--threads", "1"}, d / "log");
    EXPECT_TRUE(o.ok()) << o.err;
    return runs.emplace(job, d / "out").first->second;
}

} // namespace

TEST(Stages, PrepareTestAnalyseGiveTheFilesOfRun)
{
    const fs::path& ref = reference_run();
    const fs::path dir = fresh_dir("composed"), out = dir / "out";
    ASSERT_TRUE(run_wiredem({"prepare", tiny_job().string(), "-o", out.string(), "--threads", "2"}, dir / "log").ok());
    // In another order than run's, one by index and one by pressure.
    ASSERT_TRUE(run_wiredem({"test", out.string(), "--index", "1", "--threads", "1"}, dir / "log").ok());
    const json::value job = json::parse(read_text(tiny_job()));
    const double p0 = job.at("triaxial").at("confining_pressures_pa").as_array().at(0).to_number<double>();
    std::ostringstream p0_text;
    p0_text.precision(17);
    p0_text << p0;
    const Outcome t0 = run_wiredem({"test", out.string(), "--pressure", p0_text.str(), "--threads", "2"}, dir / "log");
    ASSERT_TRUE(t0.ok()) << t0.err;
    const Outcome a = run_wiredem({"analyse", out.string()}, dir / "log");
    ASSERT_TRUE(a.ok()) << a.err;

    EXPECT_EQ(computed(out / "summary.json"), computed(ref / "summary.json"));
    const auto diffs = h5_differences(out / "result.h5", ref / "result.h5", how_it_ran);
    EXPECT_TRUE(diffs.empty()) << joined(diffs);
    EXPECT_FALSE(fs::exists(out / "tests/test_0.checkpoint.h5"));
}

// The real binary's result.h5 holds only names of the one table of
// result.h5's names (engine/triaxial/result_names.hpp), each where the table
// puts it and with its units; and the root's and the specimen's names that
// every job writes (the optional parts: CampaignFiles.AResultFileHoldsOnlyTheTablesNames).
TEST(Stages, PrepareTestAnalyseWritesOnlyTheTablesNames)
{
    using P = wiredem::engine::ResultPlace;
    const fs::path& ref = reference_run();
    const wiredem::engine::io::File f = wiredem::engine::io::File::open_read_only(ref / "result.h5");
    const wiredem::test::ResultFileNames found = wiredem::test::result_file_names(f.root());
    for (const std::string& p : found.problems) ADD_FAILURE() << p;
    for (const wiredem::engine::ResultNameSpec& s : wiredem::engine::result_name_specs) {
        const bool always = (s.place == P::root && s.name != "free_standing")
            || (s.place == P::specimen && s.kind != wiredem::engine::ResultKind::group && s.name != "grain_clump");
        if (always) {
            EXPECT_TRUE(found.seen.contains({s.place, std::string(s.name)})) << s.name << " was not written";
        }
    }
}

TEST(Stages, TestsRunAtOnceGiveWhatTestsRunOneAfterAnotherGive)
{
    const fs::path& ref = reference_run();
    const fs::path dir = fresh_dir("concurrent"), out = dir / "out";
    // Two threads: the two tests at once, a thread each.
    const Outcome o = run_wiredem({"run", tiny_job().string(), "-o", out.string(), "--threads", "2"}, dir / "log");
    ASSERT_TRUE(o.ok()) << o.err;
    EXPECT_EQ(computed(out / "summary.json"), computed(ref / "summary.json"));
    const auto diffs = h5_differences(out / "result.h5", ref / "result.h5", how_it_ran);
    EXPECT_TRUE(diffs.empty()) << joined(diffs);
}

// Three tests on two threads: the third starts when the first of the others
// ends, and when the last of those ends its thread goes to the third, which
// stops, saves and continues from its checkpoint on both threads. The files
// are those of the tests run one after another on one thread.
TEST(Stages, ATestTakesTheThreadsOfTheTestsThatEnded)
{
    const fs::path dir = fresh_dir("handover");
    json::value job = json::parse(read_text(tiny_job()));
    job.as_object()["triaxial"].as_object()["confining_pressures_pa"] = json::array{10000, 15000, 20000};
    // The third test four times the others' loading (its plate four times
    // slower): it starts when the first of the two ends and is still far
    // from 90 % done when the second ends, so the handover happens whatever
    // the two workers' relative speeds. With three equal tests a loaded
    // machine now and then let the third pass 90 % before the second ended,
    // and no test took the spare thread (CI, 2026-12-07).
    job.as_object()["triaxial"].as_object()["plate_speed_m_per_s"] = json::array{0.04, 0.04, 0.01};
    {
        std::ofstream f(dir / "job.json");
        f << json::serialize(job);
    }
    const fs::path one = dir / "one", two = dir / "two";
    Outcome o = run_wiredem({"run", (dir / "job.json").string(), "-o", one.string(), "--threads", "1"}, dir / "log");
    ASSERT_TRUE(o.ok()) << o.err;
    // In this process, to see every progress call (the command line's
    // display drops some): the overall fraction never goes back, also where
    // a test stops and continues on more threads.
    auto spec = api::parse_job_spec(json::serialize(job));
    ASSERT_TRUE(spec.ok());
    campaign::StageControl control;
    control.threads = 2;
    std::vector<double> progress;
    std::vector<std::string> preparing; // the preparation's messages
    control.progress = [&](const char* stage, double f, const std::string& m) {
        progress.push_back(f);
        if (std::string_view(stage) == "preparing") preparing.push_back(m);
    };
    const campaign::StageError e = campaign::run(spec.value(), campaign::JobDir{two}, control);
    ASSERT_FALSE(e) << *e;
    ASSERT_GT(progress.size(), 2u);
    for (std::size_t i = 1; i < progress.size(); ++i) EXPECT_GE(progress[i], progress[i - 1]) << "call " << i;
    EXPECT_EQ(progress.back(), 1.0);
    // The preparation's messages say which phase it is in: pouring first,
    // then the settling phases (not "pouring" to the end), then done.
    ASSERT_GE(preparing.size(), 3u);
    const auto says = [](const std::string& m, const char* what) { return m.find(what) != std::string::npos; };
    EXPECT_TRUE(says(preparing[1], "pouring")) << preparing[1];
    EXPECT_TRUE(says(preparing.back(), "specimen prepared in")) << preparing.back();
    const std::string& last_step = preparing[preparing.size() - 2];
    EXPECT_TRUE(says(last_step, "settling") || says(last_step, "top plate")) << last_step;
    EXPECT_EQ(computed(two / "summary.json"), computed(one / "summary.json"));
    const auto diffs = h5_differences(two / "result.h5", one / "result.h5", how_it_ran);
    EXPECT_TRUE(diffs.empty()) << joined(diffs);
    // The test that ran last ended on both threads.
    const json::value summary = json::parse(read_text(two / "summary.json"));
    std::vector<std::int64_t> threads;
    for (const json::value& t : summary.at("tests").as_array()) threads.push_back(t.at("threads").to_number<std::int64_t>());
    EXPECT_EQ(std::count(threads.begin(), threads.end(), 2), 1) << "threads per test: " << json::serialize(summary.at("tests"));
    EXPECT_FALSE(fs::exists(two / "tests" / "test_2.checkpoint.h5"));
}

/// A stage started again and again and killed with SIGKILL after growing
/// delays (150 + 50 k ms at the k-th start), until a start finishes: whether
/// one did within 60 starts, how many kills came after `checkpoint` existed,
/// and what went wrong otherwise (a start that failed or died another way).
struct KilledRuns {
    bool done = false;
    int kills_after_a_checkpoint = 0;
    std::string error;
};
KilledRuns kill_until_it_finishes(
    const std::function<std::vector<std::string>(int attempt)>& args, const fs::path& checkpoint, const fs::path& log)
{
    KilledRuns r;
    for (int attempt = 0; attempt < 60 && !r.done; ++attempt) {
        const pid_t pid = spawn(args(attempt), log);
        if (pid <= 0) return {false, r.kills_after_a_checkpoint, "cannot start wiredem"};
        std::this_thread::sleep_for(std::chrono::milliseconds(150 + 50 * attempt));
        const bool had_checkpoint = fs::exists(checkpoint);
        ::kill(pid, SIGKILL);
        int status = 0;
        waitpid(pid, &status, 0);
        if (WIFEXITED(status)) {
            if (WEXITSTATUS(status) != 0) r.error = "exit " + std::to_string(WEXITSTATUS(status)) + ": " + read_text(log);
            r.done = true;
        } else if (WIFSIGNALED(status)) {
            r.kills_after_a_checkpoint += had_checkpoint;
        } else {
            r.error = "neither exited nor killed";
            return r;
        }
    }
    return r;
}

// SIGKILL (what the OOM killer or a node failure does) at several points of a
// test: each start continues from the last checkpoint (written every 20 ms
// here), and the test ends with the file of an uninterrupted test.
TEST(Stages, ATestKilledAtSeveralPointsContinuesToTheSameResult)
{
    const fs::path& ref = reference_run(longer_tiny_job());
    const fs::path dir = fresh_dir("killed"), out = dir / "out";
    ASSERT_TRUE(run_wiredem({"prepare", longer_tiny_job().string(), "-o", out.string(), "--threads", "1"}, dir / "log").ok());
    const KilledRuns r = kill_until_it_finishes(
        [&](int) {
            return std::vector<std::string>{
                "test", out.string(), "--index", "0", "--threads", "1", "--checkpoint-interval", "0.02"};
        },
        out / "tests/test_0.checkpoint.h5", dir / "log");
    ASSERT_EQ(r.error, "");
    ASSERT_TRUE(r.done) << "the test did not finish in 60 starts";
    EXPECT_GE(r.kills_after_a_checkpoint, 2) << "the test was not killed after a checkpoint at least twice";
    EXPECT_FALSE(fs::exists(out / "tests/test_0.checkpoint.h5"));
    // The test's own file against the reference run's: the same record.
    const auto diffs = h5_differences(out / "tests/test_0.h5", ref / "tests/test_0.h5", how_it_ran);
    EXPECT_TRUE(diffs.empty()) << joined(diffs);
}

// The same for the preparation: `wiredem prepare` killed with SIGKILL at
// several points (checkpoints every 20 ms), started again on one thread or
// two, ends with the specimen of an uninterrupted preparation.
TEST(Stages, APreparationKilledAtSeveralPointsContinuesToTheSameSpecimen)
{
    const fs::path& ref = reference_run();
    const fs::path dir = fresh_dir("killed_preparation"), out = dir / "out";
    const KilledRuns r = kill_until_it_finishes(
        [&](int attempt) {
            return std::vector<std::string>{"prepare", tiny_job().string(), "-o", out.string(), "--threads",
                std::to_string(1 + attempt % 2), "--checkpoint-interval", "0.02"};
        },
        out / "specimen.checkpoint.h5", dir / "log");
    ASSERT_EQ(r.error, "");
    ASSERT_TRUE(r.done) << "the preparation did not finish in 60 starts";
    EXPECT_GE(r.kills_after_a_checkpoint, 2) << "the preparation was not killed after a checkpoint at least twice";
    EXPECT_FALSE(fs::exists(out / "specimen.checkpoint.h5"));
    // The World (its every field and state hash) and the report in /host.
    const auto diffs = h5_differences(out / "specimen.h5", ref / "specimen.h5", how_it_ran);
    EXPECT_TRUE(diffs.empty()) << joined(diffs);
}

// SIGTERM while preparing (a server shutting down), at a later point each
// start: with the default interval (300 s) no checkpoint is due, so every one
// left behind was written on the way out; each start continues from it, and
// the specimen is the uninterrupted one.
TEST(Stages, APreparationStoppedBySigtermSavesOnItsWayOut)
{
    const fs::path& ref = reference_run();
    const fs::path dir = fresh_dir("stopped_preparation"), out = dir / "out";
    int saved_on_sigterm = 0;
    bool done = false;
    for (int attempt = 0; attempt < 60 && !done; ++attempt) {
        const pid_t pid = spawn({"prepare", tiny_job().string(), "-o", out.string(), "--threads", "1"}, dir / "log");
        ASSERT_GT(pid, 0);
        const Catching catching = wait_until_it_catches(pid, SIGTERM);
        ASSERT_NE(catching, Catching::timed_out) << "no SIGTERM handler after a minute";
        if (catching == Catching::yes) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20 + 20 * attempt));
            ::kill(pid, SIGTERM);
        }
        int status = 0;
        waitpid(pid, &status, 0);
        // Killed by the SIGTERM itself: it came after the stage had returned
        // and put the default handler back, on the process's way out (under
        // the sanitizers that takes long enough to be hit), so the stage had
        // finished; the comparison below checks its specimen.
        const bool killed_on_the_way_out = WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM;
        ASSERT_TRUE(WIFEXITED(status) || killed_on_the_way_out) << "killed by signal " << WTERMSIG(status);
        if (killed_on_the_way_out || WEXITSTATUS(status) == 0) {
            done = true;
        } else {
            ASSERT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << read_text(dir / "log");
            saved_on_sigterm += fs::exists(out / "specimen.checkpoint.h5");
        }
    }
    ASSERT_TRUE(done) << "the preparation did not finish in 60 starts";
    EXPECT_GE(saved_on_sigterm, 1) << "no checkpoint was written on SIGTERM";
    EXPECT_FALSE(fs::exists(out / "specimen.checkpoint.h5"));
    const auto diffs = h5_differences(out / "specimen.h5", ref / "specimen.h5", how_it_ran);
    EXPECT_TRUE(diffs.empty()) << joined(diffs);
}

TEST(Stages, ARunStoppedHalfWayIsContinuedByRunningItAgain)
{
    const fs::path& ref = reference_run();
    const fs::path dir = fresh_dir("rerun"), out = dir / "out";
    // The specimen and the first test, then the whole campaign: run does
    // only what is missing (test 1 and the analysis).
    ASSERT_TRUE(run_wiredem({"prepare", tiny_job().string(), "-o", out.string()}, dir / "log").ok());
    ASSERT_TRUE(run_wiredem({"test", out.string(), "--index", "0"}, dir / "log").ok());
    const auto first_test_written = fs::last_write_time(out / "tests/test_0.h5");
    const Outcome o = run_wiredem({"run", tiny_job().string(), "-o", out.string(), "--threads", "2"}, dir / "log");
    ASSERT_TRUE(o.ok()) << o.err;
    EXPECT_EQ(fs::last_write_time(out / "tests/test_0.h5"), first_test_written);
    EXPECT_EQ(computed(out / "summary.json"), computed(ref / "summary.json"));
    // Its progress starts past the preparation and the first test; its time
    // left comes from the steps it runs itself (campaign/eta.hpp): none
    // before it has run one (extrapolating that progress over its first
    // milliseconds said "eta 0 s"), none negative after.
    std::istringstream lines(o.err);
    std::string first;
    std::getline(lines, first);
    EXPECT_EQ(first.find("(eta"), std::string::npos) << first;
    for (std::string line; std::getline(lines, line);)
        EXPECT_EQ(line.find("(eta -"), std::string::npos) << line;
}

namespace {

/// The reference run's job directory without its results, in `out`: what an
/// analysis starts from.
void copy_for_analysis(const fs::path& out)
{
    fs::copy(reference_run(), out, fs::copy_options::recursive);
    for (const char* name : {"result.h5", "result.xdmf", "summary.json"}) fs::remove(out / name);
}

/// The last line of a process's stderr.
std::string last_line_of(std::string text)
{
    while (!text.empty() && text.back() == '\n') text.pop_back();
    const auto nl = text.find_last_of('\n');
    return nl == std::string::npos ? text : text.substr(nl + 1);
}

/// What a full disk must give: exit 1 (not a crash in HDF5's exit handler),
/// one line naming the reason and result.h5, no partial file, no results.
void expect_one_clean_failure(const Outcome& o, const fs::path& out)
{
    EXPECT_TRUE(WIFEXITED(o.status)) << "killed by signal " << WTERMSIG(o.status) << "\n" << o.err;
    EXPECT_EQ(o.code(), 1) << o.err;
    EXPECT_EQ(last_line_of(o.err), "wiredem: no space left on device writing " + (out / "result.h5").string()) << o.err;
    EXPECT_FALSE(fs::exists(fs::symlink_status(out / "result.h5.partial")));
    EXPECT_FALSE(fs::exists(out / "result.h5"));
    EXPECT_FALSE(fs::exists(out / "summary.json"));
}

} // namespace

// A full disk while the results are written, injected: result.h5's partial
// file is a symbolic link to /dev/full, whose every write fails with ENOSPC.
// (Before: the HDF5 error, exit 1, then SIGSEGV in libhdf5's exit handler.)
TEST(Stages, AFullDiskEndsTheAnalysisWithOneClearLine)
{
    const fs::path dir = fresh_dir("full_disk"), out = dir / "out";
    copy_for_analysis(out);
    fs::create_symlink("/dev/full", out / "result.h5.partial");
    expect_one_clean_failure(run_wiredem({"analyse", out.string()}, dir / "log"), out);
}

// The same on a real full file system: a tmpfs just large enough for the
// job directory (mounted by the test: root or CAP_SYS_ADMIN; skipped where
// mount is refused, the case above covers the same code).
TEST(Stages, AFullFileSystemEndsTheAnalysisWithOneClearLine)
{
    const fs::path dir = fresh_dir("full_tmpfs"), mnt = dir / "mnt";
    const fs::path staged = dir / "staged";
    copy_for_analysis(staged);
    std::uintmax_t bytes = 0;
    for (const auto& e : fs::recursive_directory_iterator(staged))
        if (e.is_regular_file()) bytes += (e.file_size() + 4095) / 4096 * 4096;
    fs::create_directories(mnt);
    const std::string options = "size=" + std::to_string(bytes + 16384);
    if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, options.c_str()) != 0)
        GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
    struct Unmount {
        fs::path at;
        ~Unmount() { ::umount2(at.c_str(), MNT_DETACH); }
    } unmount{mnt};
    const fs::path out = mnt / "out";
    fs::copy(staged, out, fs::copy_options::recursive);
    expect_one_clean_failure(run_wiredem({"analyse", out.string()}, dir / "log"), out);
}

TEST(Stages, BadRequestsGetClearErrors)
{
    const fs::path dir = fresh_dir("bad"), out = dir / "out";
    // A test or an analysis of a directory that was never prepared.
    Outcome o = run_wiredem({"test", out.string(), "--index", "0"}, dir / "log");
    EXPECT_EQ(o.code(), 1);
    EXPECT_NE(o.err.find("job.json"), std::string::npos) << o.err;
    o = run_wiredem({"analyse", out.string()}, dir / "log");
    EXPECT_EQ(o.code(), 1);
    EXPECT_NE(o.err.find("job.json"), std::string::npos) << o.err;

    const Outcome prepared = run_wiredem({"prepare", tiny_job().string(), "-o", out.string()}, dir / "log");
    ASSERT_TRUE(prepared.ok()) << prepared.err;
    // Its progress lines say the stage once: a message that starts with it
    // is not preceded by it ("preparing   0.0% preparing the specimen").
    EXPECT_EQ(prepared.err.find("preparing   0.0% preparing"), std::string::npos) << prepared.err;
    EXPECT_NE(prepared.err.find("  0.0% preparing the specimen"), std::string::npos) << prepared.err;
    o = run_wiredem({"test", out.string(), "--index", "2"}, dir / "log");
    EXPECT_EQ(o.code(), 1);
    EXPECT_NE(o.err.find("out of range"), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("0 to 1"), std::string::npos) << o.err;
    o = run_wiredem({"test", out.string(), "--pressure", "12345"}, dir / "log");
    EXPECT_EQ(o.code(), 1);
    EXPECT_NE(o.err.find("not one of the job's confining pressures"), std::string::npos) << o.err;
    o = run_wiredem({"test", out.string()}, dir / "log");
    EXPECT_EQ(o.code(), 2) << o.err; // usage: neither --index nor --pressure
    o = run_wiredem({"analyse", out.string()}, dir / "log");
    EXPECT_EQ(o.code(), 1);
    EXPECT_NE(o.err.find("has not run"), std::string::npos) << o.err;

    // Another job into a prepared directory.
    json::value other = json::parse(read_text(tiny_job()));
    other.as_object()["seed"] = 987654;
    {
        std::ofstream f(dir / "other.json");
        f << json::serialize(other);
    }
    o = run_wiredem({"prepare", (dir / "other.json").string(), "-o", out.string()}, dir / "log");
    EXPECT_EQ(o.code(), 1);
    EXPECT_NE(o.err.find("holds another job"), std::string::npos) << o.err;

    // A damaged specimen file is named, not a crash.
    {
        std::ofstream f(out / "specimen.h5", std::ios::trunc);
        f << "not HDF5";
    }
    o = run_wiredem({"test", out.string(), "--index", "0"}, dir / "log");
    EXPECT_EQ(o.code(), 1);
    EXPECT_NE(o.err.find("specimen.h5"), std::string::npos) << o.err;
}

// A stage runs in one process at a time: while another process holds a
// stage's lock (here this one, with flock on the lock file the stage uses),
// the stage waits --lock-wait seconds, then is refused with a message that
// names the stage, the holder and the file; the other stages are not held
// up; a holder that lets go within the wait lets the stage run. (A holder
// that dies drops its lock: the kernel's flock.)
TEST(Stages, AStageRunsInOneProcessAtATime)
{
    const fs::path dir = fresh_dir("lock"), out = dir / "out";
    fs::create_directories(out);
    struct Held {
        int fd = -1;
        explicit Held(const fs::path& file)
        {
            fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
            const std::string holder = "pid 4242 on elsewhere\n";
            EXPECT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
            EXPECT_EQ(::pwrite(fd, holder.data(), holder.size(), 0), static_cast<ssize_t>(holder.size()));
        }
        ~Held() { ::close(fd); }
    };
    {
        const Held held(out / "specimen.lock");
        const Outcome o = run_wiredem({"prepare", tiny_job().string(), "-o", out.string(), "--lock-wait", "0.3"}, dir / "log");
        EXPECT_EQ(o.code(), 1) << o.err;
        EXPECT_NE(o.err.find("the preparation of"), std::string::npos) << o.err;
        EXPECT_NE(o.err.find("(waited 0.3 s)"), std::string::npos) << o.err;
        EXPECT_NE(o.err.find("already running in another process (pid 4242 on elsewhere)"), std::string::npos) << o.err;
        EXPECT_NE(o.err.find("specimen.lock"), std::string::npos) << o.err;
        EXPECT_FALSE(fs::exists(out / "specimen.h5"));
    }
    ASSERT_TRUE(run_wiredem({"prepare", tiny_job().string(), "-o", out.string()}, dir / "log").ok());
    {
        const Held held(out / "tests" / "test_0.lock");
        Outcome o = run_wiredem({"test", out.string(), "--index", "0", "--lock-wait", "0"}, dir / "log");
        EXPECT_EQ(o.code(), 1) << o.err;
        EXPECT_NE(o.err.find("test 1/2"), std::string::npos) << o.err;
        EXPECT_NE(o.err.find("test_0.lock"), std::string::npos) << o.err;
        EXPECT_FALSE(fs::exists(out / "tests" / "test_0.h5"));
        EXPECT_FALSE(fs::exists(out / "tests" / "test_0.checkpoint.h5"));
        // Another test of the same directory is not held up.
        o = run_wiredem({"test", out.string(), "--index", "1"}, dir / "log");
        EXPECT_TRUE(o.ok()) << o.err;
    }
    {
        // A holder that lets go within the wait (a runner saving on its way
        // out): the stage waits for it and runs.
        auto held = std::make_unique<Held>(out / "tests" / "test_0.lock");
        const pid_t pid = spawn({"test", out.string(), "--index", "0", "--lock-wait", "60"}, dir / "log");
        ASSERT_GT(pid, 0);
        std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        EXPECT_FALSE(fs::exists(out / "tests" / "test_0.checkpoint.h5")) << "it ran without the lock";
        held.reset();
        int status = -1;
        waitpid(pid, &status, 0);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << read_text(dir / "log");
        EXPECT_TRUE(fs::exists(out / "tests" / "test_0.h5"));
    }
    {
        const Held held(out / "analyse.lock");
        const Outcome o = run_wiredem({"analyse", out.string(), "--lock-wait", "0"}, dir / "log");
        EXPECT_EQ(o.code(), 1) << o.err;
        EXPECT_NE(o.err.find("the analysis of"), std::string::npos) << o.err;
        EXPECT_FALSE(fs::exists(out / "summary.json"));
    }
    EXPECT_TRUE(run_wiredem({"analyse", out.string()}, dir / "log").ok());
    EXPECT_TRUE(fs::exists(out / "summary.json"));
}

// The comparison the cases above rest on sees a difference: two specimens
// poured with different seeds.
TEST(Stages, TheFileComparisonSeesAnotherSeed)
{
    const fs::path dir = fresh_dir("seeds");
    json::value other = json::parse(read_text(tiny_job()));
    other.as_object()["seed"] = 987654;
    {
        std::ofstream f(dir / "other.json");
        f << json::serialize(other);
    }
    ASSERT_TRUE(run_wiredem({"prepare", tiny_job().string(), "-o", (dir / "a").string()}, dir / "log").ok());
    ASSERT_TRUE(run_wiredem({"prepare", (dir / "other.json").string(), "-o", (dir / "b").string()}, dir / "log").ok());
    const auto diffs = h5_differences(dir / "a/specimen.h5", dir / "b/specimen.h5", how_it_ran);
    EXPECT_FALSE(diffs.empty());
    EXPECT_TRUE(h5_differences(dir / "a/specimen.h5", dir / "a/specimen.h5", how_it_ran).empty());
}

// A campaign that differs from a prepared one in its tests only takes that
// specimen instead of pouring its own (`--specimen-from`): the same file,
// and its tests run from it. A job that would prepare another specimen (here
// another seed) is refused, naming the field; the thread count does not count.
TEST(Stages, ACampaignTakesThePreparedSpecimenOfAJobThatDiffersInItsTestsOnly)
{
    const fs::path dir = fresh_dir("specimen_from"), a = dir / "a", b = dir / "b", c = dir / "c";
    ASSERT_TRUE(run_wiredem({"prepare", tiny_job().string(), "-o", a.string(), "--threads", "1"}, dir / "log").ok());
    json::value job = json::parse(read_text(tiny_job()));
    job.as_object()["name"] = "the tiny job, consolidated to the cell pressure";
    job.as_object()["triaxial"].as_object()["consolidation"] = "cell_pressure";
    job.as_object()["engine"].as_object()["threads"] = 3;
    {
        std::ofstream f(dir / "cell.json");
        f << json::serialize(job);
    }
    Outcome o = run_wiredem({"prepare", (dir / "cell.json").string(), "-o", b.string(), "--specimen-from",
                                a.string()}, dir / "log");
    ASSERT_TRUE(o.ok()) << o.err;
    EXPECT_EQ(read_text(b / "specimen.h5"), read_text(a / "specimen.h5"));
    EXPECT_NE(read_text(b / "job.json"), read_text(a / "job.json"));
    o = run_wiredem({"test", b.string(), "--index", "0", "--threads", "1"}, dir / "log");
    EXPECT_TRUE(o.ok()) << o.err;

    job.as_object()["seed"] = 987654;
    {
        std::ofstream f(dir / "other_seed.json");
        f << json::serialize(job);
    }
    o = run_wiredem({"run", (dir / "other_seed.json").string(), "-o", c.string(), "--specimen-from", a.string()},
        dir / "log");
    EXPECT_EQ(o.code(), 1);
    EXPECT_NE(o.err.find("another specimen (they differ in seed)"), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(c / "specimen.h5"));
    o = run_wiredem({"prepare", tiny_job().string(), "-o", (dir / "d").string(), "--specimen-from", c.string()}, dir / "log");
    EXPECT_EQ(o.code(), 1);
    EXPECT_NE(o.err.find("job.json"), std::string::npos) << o.err;
}

// The cuboid cell's specimen is its box, compacted to the lowest pressure:
// a job of the other cell, or of another box or lowest pressure, prepares
// another specimen; the other test settings still do not.
TEST(Stages, TheCellAndTheBoxBelongToTheSpecimen)
{
    api::JobSpec membrane;
    membrane.specimen.wire.pattern = api::WirePattern::none;
    api::JobSpec cuboid = membrane;
    cuboid.triaxial.cell = api::CellKind::cuboid;
    EXPECT_EQ(campaign::specimen_difference(membrane, cuboid), "triaxial");
    api::JobSpec other_box = cuboid;
    other_box.triaxial.cuboid.aspect_ratio = 1.0;
    EXPECT_EQ(campaign::specimen_difference(cuboid, other_box), "triaxial.cuboid.aspect_ratio");
    api::JobSpec other_lowest = cuboid;
    other_lowest.triaxial.confining_pressures_pa = {10e3, 20e3};
    EXPECT_EQ(campaign::specimen_difference(cuboid, other_lowest), "triaxial.lowest_confining_pressure_pa");
    api::JobSpec other_tests = cuboid;
    other_tests.triaxial.target_axial_strain = 0.05;
    other_tests.triaxial.confining_pressures_pa.push_back(100e3);
    EXPECT_EQ(campaign::specimen_difference(cuboid, other_tests), std::nullopt);
}

namespace {

/// A stage run again and again, each run stopped (its cancel flag set, as a
/// server's SIGTERM or a thread handover sets it) after `steps_per_run`
/// steps, on 2 and 1 threads in turn, until a run finishes: how many stops,
/// the phases (`phase_of` the checkpoint's /host) its checkpoints were saved
/// in, and what went wrong otherwise (a run that failed otherwise, or a stop
/// that left no `checkpoint`).
struct StoppedRuns {
    bool done = false;
    std::set<std::string> phases;  ///< of the checkpoints left by the stops
    int stops = 0;
    std::string error;
};
StoppedRuns stop_until_it_finishes(const std::function<campaign::StageError(const campaign::StageControl&)>& stage,
    const fs::path& checkpoint, int steps_per_run,
    const std::function<std::string(const wiredem::engine::io::Group& host)>& phase_of)
{
    StoppedRuns r;
    for (int attempt = 0; attempt < 200 && !r.done; ++attempt) {
        std::atomic<bool> stop{false};
        campaign::StageControl control;
        control.threads = attempt % 2 == 0 ? 2 : 1;
        control.cancel = &stop;
        int reports = 0; // every 500 steps (and one at the start)
        control.progress = [&](const char*, double, const std::string&) {
            if (++reports > steps_per_run / 500) stop.store(true);
        };
        const campaign::StageError e = stage(control);
        if (!e) {
            r.done = true;
            break;
        }
        if (e->find("cancelled") == std::string::npos || !fs::exists(checkpoint)) {
            r.error = "run " + std::to_string(attempt) + ": " + *e;
            return r;
        }
        ++r.stops;
        const wiredem::engine::io::File f = wiredem::engine::io::File::open_read_only(checkpoint);
        r.phases.insert(phase_of(f.root().open_group("host")));
    }
    return r;
}

} // namespace

// A cuboid-cell test stopped every 500 steps (its cancel flag set, as a
// server's SIGTERM or a thread handover sets it), before and during its
// loading, saves a checkpoint on its way out, and started again, on two
// threads and one in turn, continues from it: its file is that of the test
// run without a stop, bit for bit but for how it ran (examples/tiny-cuboid.json at one pressure, loaded to 1 %).
TEST(Stages, ACuboidTestStoppedAgainAndAgainContinuesToTheSameResult)
{
    json::value job = json::parse(read_text(source("examples/tiny-cuboid.json")));
    json::object& triaxial = job.as_object()["triaxial"].as_object();
    triaxial["confining_pressures_pa"] = json::array{10000};
    triaxial["target_axial_strain"] = 0.01;
    triaxial["snapshot_strains"] = json::array{0, 0.01};
    const fs::path dir = fresh_dir("cuboid_stops"), spec = dir / "job.json";
    std::ofstream(spec) << json::serialize(job);
    const fs::path& ref = reference_run(spec);
    const fs::path out = dir / "out";
    ASSERT_TRUE(run_wiredem({"prepare", spec.string(), "-o", out.string(), "--threads", "1"}, dir / "log").ok());
    const campaign::JobDir jd{out};
    const StoppedRuns r = stop_until_it_finishes(
        [&](const campaign::StageControl& control) { return campaign::run_test(jd, 0, control); }, jd.checkpoint(0), 500,
        [](const wiredem::engine::io::Group& host) { return host.read_int_attribute("loading") != 0 ? "loading" : "before"; });
    ASSERT_EQ(r.error, "");
    ASSERT_TRUE(r.done) << "not finished after " << r.stops << " stops";
    EXPECT_EQ(r.phases, (std::set<std::string>{"before", "loading"})) << "stopped " << r.stops << " times";
    EXPECT_FALSE(fs::exists(jd.checkpoint(0)));
    const auto diffs = h5_differences(out / "tests/test_0.h5", ref / "tests/test_0.h5", how_it_ran);
    EXPECT_TRUE(diffs.empty()) << joined(diffs);
}

// A job directory whose job.json lacks triaxial.consolidation was written
// before the field existed, when every test consolidated to the cell
// pressure (the default is `effective` since): its tests run, and its
// summary says, as it ran then. The same job without the field (today's
// default) is another job there; with cell_pressure it is the same job.
TEST(Stages, AJobDirectoryWrittenBeforeConsolidationExistedRunsAsItDidThen)
{
    const fs::path dir = fresh_dir("old_job"), out = dir / "out";
    json::value job = json::parse(read_text(tiny_job()));
    job.as_object()["triaxial"].as_object()["confining_pressures_pa"] = json::array{10000};
    {
        std::ofstream f(dir / "today.json");
        f << json::serialize(job);
    }
    job.as_object()["triaxial"].as_object()["consolidation"] = "cell_pressure";
    {
        std::ofstream f(dir / "cell.json");
        f << json::serialize(job);
    }
    ASSERT_TRUE(run_wiredem({"prepare", (dir / "cell.json").string(), "-o", out.string(), "--threads", "1"}, dir / "log").ok());
    json::value written = json::parse(read_text(out / "job.json"));
    ASSERT_EQ(written.at("triaxial").at("consolidation"), "cell_pressure");
    written.as_object()["triaxial"].as_object().erase("consolidation");
    {
        std::ofstream f(out / "job.json", std::ios::trunc);
        f << json::serialize(written) << '\n';
    }
    Outcome o = run_wiredem({"run", (dir / "today.json").string(), "-o", out.string(), "--threads", "1"}, dir / "log");
    EXPECT_EQ(o.code(), 1);
    EXPECT_NE(o.err.find("holds another job"), std::string::npos) << o.err;
    o = run_wiredem({"run", (dir / "cell.json").string(), "-o", out.string(), "--threads", "1"}, dir / "log");
    ASSERT_TRUE(o.ok()) << o.err;
    const json::value s = json::parse(read_text(out / "summary.json"));
    const json::value& t = s.at("tests").as_array().at(0);
    EXPECT_EQ(t.at("consolidation"), "cell_pressure");
    EXPECT_EQ(t.at("consolidation_target_pa").to_number<double>(), 10000.0);
    EXPECT_TRUE(t.at("consolidated").is_bool());
}

// `wiredem study run`: every point's campaign, a failing point reported
// without stopping the others, the summary grouping the seeds; run again, the
// study continues (the done point is not run again).
TEST(Stages, AStudyRunsItsPointsReportsAFailedOneAndContinuesWhenRunAgain)
{
    const fs::path dir = fresh_dir("study"), out = dir / "out";
    json::object study{{"name", "seeds"}, {"base", json::parse(read_text(tiny_job()))},
        {"vary", json::object{{"seed", json::array{1, 2}}}}};
    {
        std::ofstream f(dir / "study.json");
        f << json::serialize(study);
    }
    // Point 1's directory already holds another job: that point fails.
    fs::create_directories(out / "points/1");
    {
        std::ofstream f(out / "points/1/job.json");
        f << R"({"name": "someone else's"})";
    }
    Outcome o = run_wiredem({"study", "run", (dir / "study.json").string(), "-o", out.string(), "--jobs", "2",
                                "--threads", "2"}, dir / "log");
    EXPECT_EQ(o.code(), 1) << o.err;
    EXPECT_NE(o.err.find("1 of 2 points failed"), std::string::npos) << o.err;
    json::value s = json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s.at("points").as_array()[0].at("state"), "succeeded");
    EXPECT_EQ(s.at("points").as_array()[1].at("state"), "failed");
    EXPECT_NE(std::string(s.at("points").as_array()[1].at("error").as_string()).find("holds another job"), std::string::npos);
    EXPECT_TRUE(fs::exists(out / "summary.csv"));
    const auto first_done = fs::last_write_time(out / "points/0/summary.json");

    fs::remove_all(out / "points/1");
    o = run_wiredem({"study", "run", (dir / "study.json").string(), "-o", out.string(), "--threads", "2"}, dir / "log");
    EXPECT_EQ(o.code(), 0) << o.err;
    EXPECT_NE(o.err.find("point 1/2 (seed=1) done already"), std::string::npos) << o.err;
    EXPECT_EQ(fs::last_write_time(out / "points/0/summary.json"), first_done);
    s = json::parse(read_text(out / "summary.json"));
    const json::object& group = s.at("groups").as_array().at(0).as_object();
    EXPECT_EQ(group.at("succeeded").to_number<int>(), 2);
    const double phi0 = s.at("points").as_array()[0].at("friction_angle_deg").to_number<double>();
    const double phi1 = s.at("points").as_array()[1].at("friction_angle_deg").to_number<double>();
    // (Read here with Boost.JSON's parser, which may miss the last bit.)
    EXPECT_NEAR(group.at("friction_angle_deg").at("mean").to_number<double>(), 0.5 * (phi0 + phi1), 1e-12);
    EXPECT_NEAR(group.at("friction_angle_deg").at("sd").to_number<double>(), std::abs(phi0 - phi1) / std::sqrt(2.0), 1e-9);

    // A study with a bad point is refused before anything runs, naming it.
    study["vary"] = json::object{{"seed", json::array{1, -2}}};
    {
        std::ofstream f(dir / "bad.json");
        f << json::serialize(study);
    }
    o = run_wiredem({"study", "run", (dir / "bad.json").string(), "-o", (dir / "bad").string()}, dir / "log");
    EXPECT_EQ(o.code(), 3) << o.err;
    EXPECT_NE(o.err.find("points[1] (seed=-2): seed"), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(dir / "bad/points"));
}

namespace {

/// summary.json's free_standing without how it ran.
json::value computed_free_standing(const fs::path& summary)
{
    json::value v = json::parse(read_text(summary)).at("free_standing");
    v.as_object().erase("wall_time_s");
    v.as_object().erase("threads");
    return v;
}

/// tiny_job() at one pressure with a short free-standing test (written once
/// per process): the job of the free-standing stage cases, whose `wiredem run`
/// on one thread they share as their reference (reference_run).
const fs::path& free_standing_job()
{
    static const fs::path path = [] {
        json::value job = json::parse(read_text(tiny_job()));
        job.as_object()["triaxial"].as_object()["confining_pressures_pa"] = json::array{10000};
        job.as_object()["free_standing"] = json::object{{"enabled", true}, {"removal_time_s", 0.01},
            {"removal_distance_m", 0.002}, {"max_settling_time_s", 0.05}, {"plate_speed_m_per_s", 0.05},
            {"target_axial_strain", 0.02}, {"sample_interval_s", 0.001}};
        const fs::path p = scratch_root() / "free_standing_job.json";
        std::ofstream(p) << json::serialize(job);
        return p;
    }();
    return path;
}

} // namespace

// A job with a free-standing test: `analyse` runs it (after the tests, as
// `run` does: a cluster's analysis job has it to run) into
// tests/free_standing.h5, and the staged results are run's, bit for bit but
// for how it ran; a second `analyse` finds it done and gives the same.
TEST(Stages, AnalyseRunsTheFreeStandingTestAsRunDoes)
{
    const fs::path& spec = free_standing_job();
    const fs::path& ran = reference_run(spec);
    const fs::path dir = fresh_dir("free_standing");
    const fs::path out = dir / "staged";
    ASSERT_TRUE(run_wiredem({"prepare", spec.string(), "-o", out.string(), "--threads", "1"}, dir / "log").ok());
    ASSERT_TRUE(run_wiredem({"test", out.string(), "--index", "0", "--threads", "1"}, dir / "log").ok());
    EXPECT_FALSE(fs::exists(out / "tests/free_standing.h5"));
    const Outcome a = run_wiredem({"analyse", out.string(), "--threads", "2"}, dir / "log");
    ASSERT_TRUE(a.ok()) << a.err;
    EXPECT_TRUE(fs::exists(out / "tests/free_standing.h5"));
    EXPECT_EQ(computed_free_standing(out / "summary.json"), computed_free_standing(ran / "summary.json"));
    const auto diffs = h5_differences(out / "result.h5", ran / "result.h5", how_it_ran);
    EXPECT_TRUE(diffs.empty()) << joined(diffs);
    const Outcome again = run_wiredem({"analyse", out.string()}, dir / "log");
    ASSERT_TRUE(again.ok()) << again.err;
    EXPECT_EQ(computed_free_standing(out / "summary.json"), computed_free_standing(ran / "summary.json"));
}

// `wiredem test --free-standing` runs the free-standing test alone, before or
// without the triaxial tests (it starts from the prepared specimen, as `run`'s
// does): the staged results are run's, bit for bit but for how it ran.
TEST(Stages, TheFreeStandingTestRunsAsItsOwnStage)
{
    const fs::path& spec = free_standing_job();
    const fs::path& ran = reference_run(spec);
    const fs::path dir = fresh_dir("free_standing_stage");
    const fs::path out = dir / "staged";
    ASSERT_TRUE(run_wiredem({"prepare", spec.string(), "-o", out.string(), "--threads", "1"}, dir / "log").ok());
    Outcome o = run_wiredem({"test", out.string(), "--free-standing", "--index", "0"}, dir / "log");
    EXPECT_EQ(o.code(), 2) << o.err; // usage: one test at a time
    o = run_wiredem({"test", out.string(), "--free-standing", "--threads", "2"}, dir / "log");
    ASSERT_TRUE(o.ok()) << o.err;
    EXPECT_TRUE(fs::exists(out / "tests/free_standing.h5"));
    ASSERT_TRUE(run_wiredem({"test", out.string(), "--index", "0", "--threads", "1"}, dir / "log").ok());
    ASSERT_TRUE(run_wiredem({"analyse", out.string()}, dir / "log").ok());
    EXPECT_EQ(computed_free_standing(out / "summary.json"), computed_free_standing(ran / "summary.json"));
    const auto diffs = h5_differences(out / "result.h5", ran / "result.h5", how_it_ran);
    EXPECT_TRUE(diffs.empty()) << joined(diffs);

    // A job without a free-standing test says so.
    const fs::path plain = dir / "plain";
    ASSERT_TRUE(run_wiredem({"prepare", tiny_job().string(), "-o", plain.string(), "--threads", "1"}, dir / "log").ok());
    o = run_wiredem({"test", plain.string(), "--free-standing"}, dir / "log");
    EXPECT_EQ(o.code(), 1);
    EXPECT_NE(o.err.find("free_standing.enabled is false"), std::string::npos) << o.err;
}

// A free-standing test stopped at several points — in the removal, the
// settling, the dead load and the compression, and (a second job) the
// pull-out — saves a checkpoint on its way out, and started again, on two
// threads and one in turn, continues from it: it ends with the record of a
// test never stopped (run on one thread), bit for bit but for how it ran
// (h5_differences: every dataset and attribute). The wire is cut every loop
// before the test (breaks the World holds besides the test's own). A small
// column (examples/tiny-helix.json, 150 grains) and short phases: seconds.
TEST(Stages, AFreeStandingTestStoppedInEveryPhaseContinuesToTheSameResult)
{
    json::value job = json::parse(read_text(source("examples/tiny-helix.json")));
    job.as_object()["triaxial"].as_object()["confining_pressures_pa"] = json::array{10000};
    job.as_object()["specimen"].as_object()["wire"].as_object()["cut_every_loops"] = 1;
    const json::object quick{{"enabled", true}, {"removal_time_s", 0.005}, {"removal_distance_m", 0.002},
        {"max_settling_time_s", 0.02}, {"plate_speed_m_per_s", 0.1}, {"target_axial_strain", 0.02},
        {"sample_interval_s", 0.0005}};
    json::object loaded = quick, pulled = quick;
    loaded["dead_load_n"] = 0.05;
    loaded["dead_load_ramp_time_s"] = 0.002;
    loaded["dead_load_hold_time_s"] = 0.004;
    pulled["pull_out_speed_m_per_s"] = 0.5;
    pulled["pull_out_max_time_s"] = 0.005;
    const fs::path dir = fresh_dir("free_standing_stopped");
    fs::path prepared;
    for (const auto& [name, free_standing, phases] :
        {std::tuple{"loaded", loaded, std::set<std::string>{"removal", "settling", "dead_load", "loading"}},
            std::tuple{"pulled", pulled, std::set<std::string>{"removal", "settling", "pull_out"}}}) {
        SCOPED_TRACE(name);
        job.as_object()["free_standing"] = free_standing;
        auto spec = api::parse_job_spec(json::serialize(job));
        ASSERT_TRUE(spec.ok());
        const campaign::JobDir whole{dir / (std::string(name) + "_whole")}, stopped{dir / (std::string(name) + "_stopped")};
        campaign::StageControl control;
        control.threads = 2;
        control.specimen_from = prepared; // one pour for both jobs: they differ in their free-standing test only
        ASSERT_FALSE(campaign::prepare(spec.value(), whole, control));
        control.specimen_from = prepared = whole.root;
        ASSERT_FALSE(campaign::prepare(spec.value(), stopped, control));
        control.threads = 1;
        const campaign::StageError e = campaign::run_free_standing_test(whole, control);
        ASSERT_FALSE(e) << *e;

        const StoppedRuns r = stop_until_it_finishes(
            [&](const campaign::StageControl& c) { return campaign::run_free_standing_test(stopped, c); },
            stopped.free_standing_checkpoint(), 3000,
            [](const wiredem::engine::io::Group& host) { return host.read_string_attribute("phase"); });
        ASSERT_EQ(r.error, "");
        ASSERT_TRUE(r.done) << "not finished after " << r.stops << " stops";
        EXPECT_EQ(r.phases, phases) << "stopped " << r.stops << " times";
        EXPECT_FALSE(fs::exists(stopped.free_standing_checkpoint()));
        const auto diffs = h5_differences(stopped.free_standing(), whole.free_standing(), how_it_ran);
        EXPECT_TRUE(diffs.empty()) << joined(diffs);
    }
}
