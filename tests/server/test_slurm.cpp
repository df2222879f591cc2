// The Slurm executor's pure pieces (server/slurm.hpp), without a cluster:
// option checks name the option, a batch script passes its words to wiredem
// untouched by the shell (run here with /bin/sh and a stand-in wiredem),
// squeue's and sacct's lines are read as Slurm prints them (22.05), and a
// job's verdict follows from its units. The real cluster: tests/slurm.
#include "slurm.hpp"

#include "api/derived.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

using namespace wiredem::server;
namespace fs = std::filesystem;

namespace {

SlurmOptions usable_options()
{
    SlurmOptions o;
    o.wiredem = "/bin/true";
    return o;
}

std::string problem_of(const SlurmOptions& o) { return slurm_options_problem(o).value_or(""); }

std::string read_all(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// A fresh folder under the test's temporary directory.
fs::path fresh_dir(const std::string& name)
{
    const fs::path d = fs::temp_directory_path() / ("wiredem-slurm-unit-" + std::to_string(::getpid())) / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

} // namespace

TEST(SlurmOptions, EveryProblemNamesItsOption)
{
    EXPECT_EQ(problem_of(usable_options()), "");
    SlurmOptions o = usable_options();
    o.wiredem = "relative/wiredem";
    EXPECT_NE(problem_of(o).find("--slurm-wiredem"), std::string::npos);
    o.wiredem = "/nonexistent/wiredem";
    EXPECT_NE(problem_of(o).find("--slurm-wiredem /nonexistent/wiredem is not an executable"), std::string::npos);

    o = usable_options();
    o.partition = "batch;rm -rf /";
    EXPECT_NE(problem_of(o).find("--slurm-partition"), std::string::npos);
    o.partition = "batch,long";
    EXPECT_EQ(problem_of(o), "");

    o = usable_options();
    o.account = "proj 1";
    EXPECT_NE(problem_of(o).find("--slurm-account"), std::string::npos);

    for (const char* good : {"30", "30:00", "1:30:00", "2-12", "2-12:30", "2-12:30:15"}) {
        o = usable_options();
        o.time_limit = good;
        EXPECT_EQ(problem_of(o), "") << good;
    }
    for (const char* bad : {"1h", "-5", "1:2:3:4", "2-", "soon", ":30", "30:", "1::2", "2-1:2:3:4", "1-2-3", "2-12-"}) {
        o = usable_options();
        o.time_limit = bad;
        EXPECT_NE(problem_of(o).find("--slurm-time-limit '" + std::string(bad) + "'"), std::string::npos) << bad;
    }

    o = usable_options();
    o.cpus_per_task = 0;
    EXPECT_NE(problem_of(o).find("--slurm-cpus-per-task"), std::string::npos);
}

TEST(SlurmOptions, SbatchOptionsAreWholeArgumentsAndLeaveTheExecutorsOwnAlone)
{
    SlurmOptions o = usable_options();
    o.sbatch_options = {"--qos=high", "--mem=4G", "-N1", "--exclusive"};
    EXPECT_EQ(problem_of(o), "");
    o.sbatch_options = {"high"};  // a value given apart from its option
    EXPECT_NE(problem_of(o).find("--slurm-sbatch-option 'high': give each sbatch option with its value as one argument"),
        std::string::npos);
    o.sbatch_options = {"--comment=a\nb"};
    EXPECT_NE(problem_of(o).find("line break"), std::string::npos);
    for (const char* reserved : {"--array=0-9", "-a0-9", "--dependency=afterany:1", "--output=x", "-ox", "--wrap=ls",
             "--job-name=x", "--chdir=/", "--partition=p", "-pp", "--time=5", "-t5", "--cpus-per-task=4", "--parsable"}) {
        o.sbatch_options = {reserved};
        EXPECT_NE(problem_of(o).find("--slurm-sbatch-option '" + std::string(reserved) + "'"), std::string::npos)
            << reserved;
    }
    o.sbatch_options = {"--partition=p"};
    EXPECT_NE(problem_of(o).find("use --slurm-partition"), std::string::npos);
}

TEST(SlurmSubmission, SbatchGetsTheChainTheArrayAndTheLogs)
{
    SlurmOptions o = usable_options();
    o.partition = "batch";
    o.account = "proj";
    o.time_limit = "2:00:00";
    o.cpus_per_task = 4;
    o.sbatch_options = {"--qos=high"};
    const SlurmFiles files{"/data/100%/jobs/0123456789abcdef01234567/work"};
    const std::string id = "0123456789abcdef01234567";

    const auto prepare = sbatch_arguments(SlurmStage::prepare, id, files, o, 0, 3);
    const std::vector<std::string> expected_prepare{"--parsable", "--job-name=wiredem-" + id,
        "--chdir=/data/100%/jobs/" + id + "/work", "--output=/data/100%%/jobs/" + id + "/work/slurm/prepare.out",
        "--error=/data/100%%/jobs/" + id + "/work/slurm/prepare.err", "--ntasks=1", "--cpus-per-task=4",
        "--partition=batch", "--account=proj", "--time=2:00:00", "--qos=high",
        "/data/100%/jobs/" + id + "/work/slurm/prepare.sh"};
    EXPECT_EQ(prepare, expected_prepare);

    const auto tests = sbatch_arguments(SlurmStage::test, id, files, o, 41, 3);
    const auto has = [&](const std::vector<std::string>& args, const std::string& a) {
        return std::find(args.begin(), args.end(), a) != args.end();
    };
    EXPECT_TRUE(has(tests, "--dependency=afterok:41"));
    EXPECT_TRUE(has(tests, "--kill-on-invalid-dep=yes"));
    EXPECT_TRUE(has(tests, "--array=0-2"));
    EXPECT_TRUE(has(tests, "--output=/data/100%%/jobs/" + id + "/work/slurm/test_%a.out"));
    EXPECT_EQ(tests.back(), "/data/100%/jobs/" + id + "/work/slurm/test.sh");
    const auto analyse = sbatch_arguments(SlurmStage::analyse, id, files, o, 42, 3);
    EXPECT_TRUE(has(analyse, "--dependency=afterok:42"));
    EXPECT_FALSE(std::any_of(analyse.begin(), analyse.end(), [](const std::string& a) { return a.rfind("--array", 0) == 0; }));
}

TEST(SlurmSubmission, TheBatchScriptPassesItsWordsToWiredemAsTheyAreAndLeavesTheExitStatus)
{
    // A work folder whose path would run commands if the shell read it
    // unquoted, and a stand-in wiredem that writes its arguments one per line.
    const fs::path root = fresh_dir("script");
    const SlurmFiles files{root / "it's $(touch pwned) `x` \"q\" ;&|" / "work"};
    fs::create_directories(files.dir());
    const fs::path args_file = root / "args";
    const fs::path fake = root / "fake wiredem";
    std::ofstream(fake) << "#!/bin/sh\nfor a in \"$@\"; do printf '%s\\n' \"$a\"; done > '" << args_file.string()
                        << "'\nexit 3\n";
    fs::permissions(fake, fs::perms::owner_all);
    SlurmOptions o = usable_options();
    o.wiredem = fake;
    o.cpus_per_task = 2;

    const fs::path script = files.script(SlurmStage::test);
    std::ofstream(script) << slurm_batch_script(SlurmStage::test, "0123456789abcdef01234567", files, o, 0.25);
    const std::string command = "cd '" + root.string() + "' && SLURM_ARRAY_TASK_ID=1 /bin/sh \"$0\"";
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::execl("/bin/sh", "sh", "-c", command.c_str(), script.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 3);  // wiredem's status is the task's
    EXPECT_EQ(read_all(args_file), "test\n" + files.out().string() + "\n--index\n1\n--threads\n2\n--progress\njson\n"
                                       "--checkpoint-interval\n0.25\n");
    EXPECT_EQ(read_all(files.log(SlurmStage::test, 1, "exit")), "3\n");
    EXPECT_FALSE(fs::exists(root / "pwned"));
    EXPECT_FALSE(fs::exists(files.log(SlurmStage::test, 1, "exit.part")));
    // The preparation and the analysis (which runs the free-standing test)
    // keep checkpoints at the server's interval too, not at the runner's default.
    for (const SlurmStage stage : {SlurmStage::prepare, SlurmStage::analyse}) {
        const std::string text = slurm_batch_script(stage, "0123456789abcdef01234567", files, o, 0.25);
        EXPECT_NE(text.find("'--checkpoint-interval' '0.25'"), std::string::npos) << text;
    }
    fs::remove_all(root.parent_path());
}

TEST(SlurmState, SqueueLinesAsSlurmPrintsThem)
{
    // squeue --noheader --array --states=all --format='%i|%F|%K|%T|%r', Slurm 22.05.
    const std::string out = "5|5|N/A|PENDING|Dependency\n"
                            "3|3|N/A|COMPLETED|None\n"
                            "4_2|4|2|FAILED|NonZeroExitCode\n"
                            "4_0|4|0|RUNNING|None\n"
                            "4_[5-6]|4|[5-6%1]|PENDING|JobArrayTaskLimit\n"
                            "garbage line\n"
                            "7|x|N/A|RUNNING|None\n";
    const auto lines = parse_squeue(out);
    ASSERT_EQ(lines.size(), 6u);
    EXPECT_EQ(lines[0].job, 5);
    EXPECT_FALSE(lines[0].task);
    EXPECT_EQ(lines[0].reason, "Dependency");
    EXPECT_EQ(lines[2].job, 4);
    EXPECT_EQ(lines[2].task, 2u);
    EXPECT_EQ(lines[2].state, "FAILED");
    EXPECT_EQ(lines[4].task, 5u);
    EXPECT_EQ(lines[5].task, 6u);
    EXPECT_EQ(parse_sbatch_id("1234\n"), 1234);
    EXPECT_EQ(parse_sbatch_id("1234;cluster\n"), 1234);
    EXPECT_FALSE(parse_sbatch_id("sbatch: error: Batch job submission failed\n"));

    const auto acct = parse_sacct("12|COMPLETED\n13_0|COMPLETED\n13_1|CANCELLED by 0\n13_[2-3]|PENDING\n14|PENDING\n");
    ASSERT_EQ(acct.size(), 6u);
    EXPECT_TRUE(parse_sacct("15_|FAILED\n16|\nx|RUNNING\n").empty()); // no task list, no state, no job id
    EXPECT_EQ(acct[2].task, 1u);
    EXPECT_EQ(slurm_state_kind(acct[2].state), SlurmUnit::State::failed);
    EXPECT_EQ(acct[4].task, 3u);
}

TEST(SlurmState, TheVerdictFollowsTheUnits)
{
    const SlurmIds ids{3, 4, 5, 0};
    const auto line = [](std::int64_t job, std::optional<std::size_t> task, const char* state) {
        return SlurmJobLine{job, task, state, "None"};
    };
    using K = SlurmVerdict::Kind;
    // Preparing: the rest waits on it.
    auto units = slurm_units(ids, 2,
        {line(3, {}, "RUNNING"), line(4, 0, "PENDING"), line(4, 1, "PENDING"), line(5, {}, "PENDING")}, {});
    EXPECT_EQ(slurm_verdict(units).kind, K::running);
    // A failed test is the verdict, not the analysis it cancelled.
    units = slurm_units(ids, 2,
        {line(3, {}, "COMPLETED"), line(4, 0, "COMPLETED"), line(4, 1, "FAILED"), line(5, {}, "CANCELLED")}, {});
    EXPECT_EQ(slurm_verdict(units).kind, K::failed);
    EXPECT_EQ(slurm_verdict(units).unit, 2u);
    EXPECT_EQ(slurm_unit_name(2, 2), "test 2 of 2");
    // Forgotten by Slurm (MinJobAge): the exit markers tell.
    units = slurm_units(ids, 2, {}, {0, 0, 0, 0});
    EXPECT_EQ(slurm_verdict(units).kind, K::succeeded);
    units = slurm_units(ids, 2, {line(5, {}, "RUNNING")}, {0, 0, 1, std::nullopt});
    EXPECT_EQ(slurm_verdict(units).kind, K::failed);
    EXPECT_EQ(units[2].slurm_state, "exit 1");
    // Nothing known, nothing done: lost, to be submitted again.
    units = slurm_units(ids, 2, {}, {0, std::nullopt, std::nullopt, std::nullopt});
    EXPECT_EQ(slurm_verdict(units).kind, K::lost);
    // Another job's lines (a stray of an earlier submission) do not count.
    units = slurm_units(ids, 2, {line(9, {}, "RUNNING"), line(4, 7, "RUNNING")}, {});
    EXPECT_EQ(slurm_verdict(units).kind, K::lost);
}

TEST(SlurmState, TheStagesSharesSumToTheWholeJob)
{
    wiredem::api::WorkEstimate w;
    w.preparation_steps = 1e5;
    w.test_steps = {4.5e5, 3e5, 1.5e5};  // slower plates at the low pressures
    const auto s = wiredem::api::progress_shares(w);
    const std::vector<double> all{1.0, 1.0, 1.0};
    EXPECT_EQ(s.overall(1.0, all, 1.0, 0.0), 1.0);  // exactly: what is left is nothing
    EXPECT_DOUBLE_EQ(s.overall(0.0, {}, 0.0, 0.0), 0.0);
    EXPECT_DOUBLE_EQ(s.overall(1.0, {}, 0.0, 0.0), 0.95 * 1e5 / 1e6);
    // Each test in proportion to its steps: the first is half the tests' work.
    const std::vector<double> first{1.0, 0.0, 0.0};
    EXPECT_DOUBLE_EQ(s.overall(1.0, first, 0.0, 0.0), 0.95 * (1e5 + 4.5e5) / 1e6);
    EXPECT_EQ(s.free_standing, 0.0) << "no share for a test the job does not run";
}

// The free-standing test is one more test of its estimated steps: its share
// is in proportion to them, the triaxial tests' shrink to make room, and a
// job whose every part is done is at exactly 1.
TEST(SlurmState, TheFreeStandingTestHasItsShareOfTheProgress)
{
    wiredem::api::WorkEstimate w;
    w.preparation_steps = 1e5;
    w.test_steps = {4.5e5, 3e5, 1.5e5};
    w.free_standing_steps = 1e5;  // a tenth of the job's steps
    const auto s = wiredem::api::progress_shares(w);
    const std::vector<double> all{1.0, 1.0, 1.0};
    EXPECT_EQ(s.overall(1.0, all, 1.0, 1.0), 1.0);
    EXPECT_NEAR(s.overall(1.0, {}, 0.0, 0.0), 0.95 * 1e5 / 1.1e6, 1e-12);
    EXPECT_NEAR(s.overall(1.0, all, 0.0, 0.0), 0.95 * 1e6 / 1.1e6, 1e-12);
    EXPECT_NEAR(s.overall(1.0, all, 0.0, 0.5), 0.95 * (1e6 + 0.5e5) / 1.1e6, 1e-12);
    EXPECT_NEAR(s.overall(1.0, all, 0.0, 1.0), 0.95, 1e-12);
}
