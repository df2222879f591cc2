// The executor options of wiredem-server (--executor, --slurm-*): checked
// as the server starts, each error naming its option, before anything runs.
// The Slurm executor itself runs in tests/slurm (a real cluster) and its
// pieces in test_slurm.cpp.
#include "harness.hpp"

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

} // namespace wiredem::test
