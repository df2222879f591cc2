// The executor options of wiredem-server (--executor, --slurm-*): checked
// as the server starts, each error naming its option, before anything runs.
// The Slurm executor itself runs in tests/slurm (a real cluster) and its
// pieces in test_slurm.cpp.
#include "harness.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <cstdlib>

namespace wiredem::test {
namespace {
namespace fs = std::filesystem;

/// Exit code and log of a server started with `args` on a fresh data directory.
std::pair<int, std::string> start_with(const std::vector<std::string>& args)
{
    TempDir tmp;
    std::string log;
    const int code = server_exit_code(tmp.path() / "data", args, log);
    return {code, log};
}

} // namespace

TEST(ExecutorOptions, SlurmOptionsWithoutTheSlurmExecutorAreAUsageError)
{
    const auto [code, log] = start_with({"--slurm-partition", "batch"});
    EXPECT_EQ(code, 2) << log;
    EXPECT_NE(log.find("--slurm-partition applies to --executor slurm only"), std::string::npos) << log;
    const auto [code2, log2] = start_with({"--executor", "pbs"});
    EXPECT_EQ(code2, 2) << log2;
    EXPECT_NE(log2.find("--executor"), std::string::npos) << log2;
}

TEST(ExecutorOptions, ABadSlurmOptionStopsTheServerNamingIt)
{
    // The sbatch option, given as one argument, is taken; the time limit is not.
    auto [code, log] = start_with({"--executor", "slurm", "--slurm-sbatch-option=--qos=high", "--slurm-time-limit", "1h"});
    EXPECT_EQ(code, 3) << log;
    EXPECT_NE(log.find("--slurm-time-limit '1h'"), std::string::npos) << log;

    std::tie(code, log) = start_with({"--executor", "slurm", "--slurm-sbatch-option=--array=0-9"});
    EXPECT_EQ(code, 3) << log;
    EXPECT_NE(log.find("--slurm-sbatch-option '--array=0-9': --array is set by the executor"), std::string::npos) << log;

    std::tie(code, log) = start_with({"--executor", "slurm", "--slurm-wiredem", "/nonexistent/wiredem"});
    EXPECT_EQ(code, 3) << log;
    EXPECT_NE(log.find("--slurm-wiredem /nonexistent/wiredem is not an executable file"), std::string::npos) << log;

    std::tie(code, log) = start_with({"--executor", "slurm", "--slurm-cpus-per-task", "0"});
    EXPECT_EQ(code, 2) << log;
    EXPECT_NE(log.find("--slurm-cpus-per-task"), std::string::npos) << log;
}

TEST(ExecutorOptions, TheSlurmExecutorWithoutSlurmsCommandsSaysWhichIsMissing)
{
    const char* old = std::getenv("PATH");
    const std::string saved = old ? old : "";
    ::setenv("PATH", "/nonexistent", 1);
    const auto [code, log] = start_with({"--executor", "slurm", "--slurm-wiredem", "/bin/true"});
    ::setenv("PATH", saved.c_str(), 1);
    EXPECT_EQ(code, 3) << log;
    EXPECT_NE(log.find("sbatch is not on PATH"), std::string::npos) << log;
}

/// Fake Slurm client commands in `dir`: sbatch and scancel that do nothing,
/// and squeue that prints nothing, or fails as squeue does without a
/// controller when `controller` is false.
void fake_slurm(const fs::path& dir, bool controller)
{
    fs::create_directories(dir);
    for (const char* name : {"sbatch", "scancel", "squeue"}) {
        std::string script = "#!/bin/sh\nexit 0\n";
        if (std::string(name) == "squeue" && !controller)
            script = "#!/bin/sh\necho 'slurm_load_jobs error: Unable to contact slurm controller (connect failure)' >&2\nexit 1\n";
        write_file(dir / name, script);
        fs::permissions(dir / name, fs::perms::owner_all);
    }
}

/// Runs `body` with `dir` first on PATH.
template <class F>
void with_path_first(const fs::path& dir, F body)
{
    const char* old = std::getenv("PATH");
    const std::string saved = old ? old : "";
    ::setenv("PATH", (dir.string() + ":" + saved).c_str(), 1);
    body();
    ::setenv("PATH", saved.c_str(), 1);
}

// Slurm's commands but no controller: the server does not start (exit 3,
// squeue's error said), instead of failing its first job with it.
TEST(ExecutorOptions, TheSlurmExecutorWithoutAControllerDoesNotStart)
{
    TempDir tmp;
    fake_slurm(tmp.path() / "bin", false);
    with_path_first(tmp.path() / "bin", [&] {
        const auto [code, log] = start_with({"--executor", "slurm", "--slurm-wiredem", "/bin/true"});
        EXPECT_EQ(code, 3) << log;
        EXPECT_NE(log.find("the Slurm controller does not answer"), std::string::npos) << log;
        EXPECT_NE(log.find("Unable to contact slurm controller"), std::string::npos) << log;
    });
}

// Under Slurm, health's threads_per_job is what each Slurm job gets
// (--slurm-cpus-per-task), not the local executor's --threads-per-job.
TEST(ExecutorOptions, HealthUnderSlurmSaysTheSlurmJobsThreads)
{
    TempDir tmp;
    fake_slurm(tmp.path() / "bin", true);
    with_path_first(tmp.path() / "bin", [&] {
        ServerProcess server(tmp.path() / "data",
            {"--executor", "slurm", "--slurm-wiredem", "/bin/true", "--slurm-cpus-per-task", "3", "--threads-per-job", "2"});
        const auto health = http(server.port(), "GET", "/v1/health");
        ASSERT_EQ(health.status, 200);
        EXPECT_EQ(health.json().at("threads_per_job").to_number<int>(), 3) << health.body;
        EXPECT_EQ(health.json().at("executor").as_string(), "slurm");
    });
}

} // namespace wiredem::test
