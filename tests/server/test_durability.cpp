// A job accepted with 201 is never lost: kill -9 the server mid-run, start it
// again on the same data directory, and every job finishes with its files;
// SIGTERM puts the running job back in the queue and exits 0.
#include "harness.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>

#include <cstdlib>
#include <fstream>
#include <thread>

namespace wiredem::test {
namespace {
namespace fs = std::filesystem;
namespace json = boost::json;

bool is_running(const json::value& j) { return state_of(j) == "running"; }
bool is_final(const json::value& j)
{
    const auto s = state_of(j);
    return s == "succeeded" || s == "failed" || s == "cancelled";
}

/// True while some process still has `needle` in its command line (the fake
/// runner with a job's directory in its arguments).
bool process_with_arg_exists(const std::string& needle)
{
    for (const auto& entry : fs::directory_iterator("/proc")) {
        const auto name = entry.path().filename().string();
        if (name.find_first_not_of("0123456789") != std::string::npos) continue;
        std::string cmdline = read_file(entry.path() / "cmdline");
        if (cmdline.find(needle) != std::string::npos) return true;
    }
    return false;
}

TEST(Durability, KillNineMidRunThenRestartFinishesEveryJob)
{
    TempDir tmp;
    const fs::path data = tmp.path() / "data";
    std::vector<std::string> ids;
    {
        ServerProcess server(data, {"--jobs", "1"}, 0.1);
        for (int i = 0; i < 3; ++i) {
            const auto r = http(server.port(), "POST", "/v1/jobs", R"({"name": "durable)" + std::to_string(i) + "\"}");
            ASSERT_EQ(r.status, 201);
            ids.push_back(std::string(r.json().at("id").as_string()));
        }
        ASSERT_EQ(state_of(poll_job(server.port(), ids[0], is_running)), "running");
        server.kill_hard();
    }
    // The orphaned runner got SIGTERM from the kernel (PR_SET_PDEATHSIG) and
    // does not write into the job directory behind the next server's back.
    const std::string work = (data / "jobs" / ids[0] / "work").string();
    for (int i = 0; i < 100 && process_with_arg_exists(work); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_FALSE(process_with_arg_exists(work));

    ServerProcess restarted(data, {"--jobs", "1"}, 0.02);
    for (const auto& id : ids) {
        const auto job = poll_job(restarted.port(), id, is_final);
        EXPECT_EQ(state_of(job), "succeeded") << id << "\n" << restarted.log();
        EXPECT_TRUE(fs::is_regular_file(data / "jobs" / id / "result.h5"));
        EXPECT_TRUE(fs::is_regular_file(data / "jobs" / id / "summary.json"));
    }
    EXPECT_EQ(poll_job(restarted.port(), ids[0], is_final).at("attempts").to_number<int>(), 2)
        << "the interrupted attempt counts";
    EXPECT_NE(restarted.log().find("job " + ids[0] + ": interrupted by a restart, queued again"), std::string::npos);
    const auto fetched = run_client({"fetch", ids[0], "-o", (tmp.path() / "out").string(), "--server", restarted.url()});
    EXPECT_EQ(fetched.exit_code, 0) << fetched.err;
}

TEST(Durability, SigtermRequeuesTheRunningJobAndExitsCleanly)
{
    TempDir tmp;
    const fs::path data = tmp.path() / "data";
    std::string id;
    {
        ServerProcess server(data, {}, 0.2);
        const auto r = http(server.port(), "POST", "/v1/jobs", R"({"name": "slow-term"})");
        ASSERT_EQ(r.status, 201);
        id = std::string(r.json().at("id").as_string());
        ASSERT_EQ(state_of(poll_job(server.port(), id, is_running)), "running");
        const auto t0 = std::chrono::steady_clock::now();
        const int status = server.terminate();
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << server.log();
        EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
        EXPECT_NE(server.log().find("stopped by shutdown, queued again"), std::string::npos) << server.log();
    }
    ServerProcess restarted(data, {}, 0.02);
    const auto job = poll_job(restarted.port(), id, is_final);
    EXPECT_EQ(state_of(job), "succeeded") << restarted.log();
    EXPECT_EQ(job.at("attempts").to_number<int>(), 1) << "a graceful stop does not count as an attempt";
}

int exit_code_on(const fs::path& data_dir, std::string& log) { return server_exit_code(data_dir, {}, log); }

/// A data directory whose store holds one job, its server stopped cleanly.
void make_store_with_one_job(const fs::path& data)
{
    ServerProcess server(data);
    ASSERT_EQ(http(server.port(), "POST", "/v1/jobs", "{}").status, 201);
    ASSERT_EQ(server.terminate(), 0);
}

TEST(Durability, ADamagedStoreStopsTheServerWithExitCode3AndAMessage)
{
    // A store with a job in it, then a page in the middle overwritten (what a
    // torn write or a bad disk leaves). The server must not abort at its
    // first read of the bad page but refuse to start, naming the file.
    TempDir tmp;
    const fs::path data = tmp.path() / "data";
    ASSERT_NO_FATAL_FAILURE(make_store_with_one_job(data));
    const fs::path db = data / "jobs.sqlite3";
    ASSERT_GT(fs::file_size(db), 8192u);
    {
        std::fstream f(db, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(4096); // page 2 (the jobs table's root), header and all
        const std::string junk(4096, '\x55');
        f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
    }
    std::string log;
    EXPECT_EQ(exit_code_on(data, log), 3) << log;
    EXPECT_NE(log.find("jobs.sqlite3"), std::string::npos) << log;
}

TEST(Durability, AMissingTokenFileIsASetupError)
{
    // Exit 3 (cannot set up), as documented, not 2 (bad command line).
    TempDir tmp;
    const std::string command = std::string("timeout 10 '") + WIREDEM_SERVER_BIN + "' --listen 127.0.0.1:0 --data-dir '"
                              + (tmp.path() / "data").string() + "' --runner /bin/true --token-file '"
                              + (tmp.path() / "no-such-token").string() + "' > /dev/null 2>&1";
    const int status = std::system(command.c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 3) << status;
}

TEST(Durability, ListensOnAHostName)
{
    // --listen localhost:PORT (documented as HOST:PORT) binds the name's
    // address, and requests naming either are served.
    TempDir tmp;
    const fs::path port_file = tmp.path() / "port";
    const std::string command = std::string("timeout 5 '") + WIREDEM_SERVER_BIN + "' --listen localhost:0 --port-file '"
                              + port_file.string() + "' --data-dir '" + (tmp.path() / "data").string()
                              + "' --runner /bin/true > /dev/null 2>&1 &";
    ASSERT_EQ(std::system(command.c_str()), 0);
    for (int i = 0; i < 100 && !fs::exists(port_file); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(30));
    ASSERT_TRUE(fs::exists(port_file)) << "the server did not start on localhost";
    const auto port = static_cast<std::uint16_t>(std::stoi(read_file(port_file)));
    EXPECT_EQ(http(port, "GET", "/v1/health", {}, {{"Host", "localhost:" + std::to_string(port)}}).status, 200);
    EXPECT_EQ(http(port, "GET", "/v1/health").status, 200); // Host: 127.0.0.1
}

TEST(Durability, AStoreWithAForgedJobIdIsRefused)
{
    // Ids name folders under DATA_DIR/jobs; one written into the database by
    // anything but the server (here: sqlite3 by hand) could lead outside it.
    TempDir tmp;
    const fs::path data = tmp.path() / "data";
    ASSERT_NO_FATAL_FAILURE(make_store_with_one_job(data));
    const std::string forge = "sqlite3 '" + (data / "jobs.sqlite3").string()
                            + "' \"UPDATE jobs SET id = '../../x'\"";
    ASSERT_EQ(std::system(forge.c_str()), 0) << "needs the sqlite3 command";
    std::string log;
    EXPECT_EQ(exit_code_on(data, log), 3) << log;
    EXPECT_NE(log.find("'../../x' is not 24 hex digits"), std::string::npos) << log;
}

TEST(Durability, AJobStoredWithoutConsolidationRunsAsItWouldHaveThen)
{
    // A job accepted before triaxial.consolidation existed (its stored spec,
    // complete then, lacks the field: made here with sqlite3) consolidated to
    // the cell pressure; the default is `effective` since. The server reads it
    // as it ran then (server::stored_spec, also what the runner is given).
    TempDir tmp;
    const fs::path data = tmp.path() / "data";
    ASSERT_NO_FATAL_FAILURE(make_store_with_one_job(data));
    const std::string forge = "sqlite3 '" + (data / "jobs.sqlite3").string()
                            + "' \"UPDATE jobs SET spec = json_remove(spec, '$.triaxial.consolidation')\"";
    ASSERT_EQ(std::system(forge.c_str()), 0) << "needs the sqlite3 command";
    ServerProcess server(data);
    const auto list = http(server.port(), "GET", "/v1/jobs");
    ASSERT_EQ(list.status, 200);
    const std::string id(list.json().at("jobs").as_array().at(0).at("id").as_string());
    const auto job = http(server.port(), "GET", "/v1/jobs/" + id);
    ASSERT_EQ(job.status, 200);
    EXPECT_EQ(job.json().at("spec").at("triaxial").at("consolidation"), "cell_pressure");
    // A job submitted today takes today's default.
    const auto fresh = http(server.port(), "POST", "/v1/jobs", "{}");
    ASSERT_EQ(fresh.status, 201);
    const auto now = http(server.port(), "GET", "/v1/jobs/" + std::string(fresh.json().at("id").as_string()));
    EXPECT_EQ(now.json().at("spec").at("triaxial").at("consolidation"), "effective");
}

TEST(Durability, AnEmptyStoreBesideJobFoldersIsRefused)
{
    // A 0-byte jobs.sqlite3 (or none) while job folders remain: starting an
    // empty store would forget those jobs.
    TempDir tmp;
    const fs::path data = tmp.path() / "data";
    fs::create_directories(data / "jobs" / "0123456789abcdef01234567");
    std::ofstream(data / "jobs.sqlite3").close();
    std::string log;
    EXPECT_EQ(exit_code_on(data, log), 3) << log;
    EXPECT_NE(log.find("the job store was lost"), std::string::npos) << log;
    fs::remove(data / "jobs.sqlite3");
    EXPECT_EQ(exit_code_on(data, log), 3) << log;
    EXPECT_NE(log.find("is missing"), std::string::npos) << log;
    // Without job folders a fresh store starts (and serves until stopped).
    fs::remove_all(data / "jobs");
    EXPECT_NO_THROW(ServerProcess server(data));
}

/// The pid of the process whose command line holds `needle` and names the
/// fake runner (the runner of one job), or 0.
pid_t runner_pid_with_arg(const std::string& needle)
{
    for (const auto& entry : fs::directory_iterator("/proc")) {
        const auto name = entry.path().filename().string();
        if (name.find_first_not_of("0123456789") != std::string::npos) continue;
        const std::string cmdline = read_file(entry.path() / "cmdline");
        if (cmdline.find(needle) != std::string::npos && cmdline.find("fake_runner.sh") != std::string::npos)
            return static_cast<pid_t>(std::stoi(name));
    }
    return 0;
}

TEST(Durability, ARunnerKilledBySigkillIsTriedOnceMoreThenFailsSayingWhy)
{
    // What the kernel's OOM killer does: SIGKILL to the runner. The job goes
    // back to the queue once (the attempt counts) and succeeds; killed in
    // both attempts, it fails and says it was likely out of memory.
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--jobs", "1"}, 0.3);
    auto kill_runner = [&](const std::string& id) {
        poll_job(server.port(), id, is_running);
        pid_t pid = 0;
        for (int i = 0; i < 200 && pid == 0; ++i) {
            pid = runner_pid_with_arg(id);
            if (pid == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        ASSERT_GT(pid, 0) << "no runner for job " << id;
        ASSERT_EQ(::kill(pid, SIGKILL), 0);
    };
    const auto once = http(server.port(), "POST", "/v1/jobs", R"({"name": "killed once"})");
    ASSERT_EQ(once.status, 201);
    const std::string id1(once.json().at("id").as_string());
    kill_runner(id1);
    const json::value done = poll_job(server.port(), id1, is_final, std::chrono::milliseconds(30000));
    EXPECT_EQ(state_of(done), "succeeded") << json::serialize(done);
    EXPECT_EQ(done.at("attempts").to_number<int>(), 2);

    const auto twice = http(server.port(), "POST", "/v1/jobs", R"({"name": "killed twice"})");
    ASSERT_EQ(twice.status, 201);
    const std::string id2(twice.json().at("id").as_string());
    kill_runner(id2);
    // The second attempt: wait until it has started (attempts 2), then kill it.
    poll_job(server.port(), id2, [](const json::value& j) { return j.at("attempts").to_number<int>() == 2; },
        std::chrono::milliseconds(20000));
    kill_runner(id2);
    const json::value failed = poll_job(server.port(), id2, is_final, std::chrono::milliseconds(30000));
    EXPECT_EQ(state_of(failed), "failed") << json::serialize(failed);
    const std::string error(failed.at("error").as_string());
    EXPECT_NE(error.find("likely out of memory"), std::string::npos) << error;
    EXPECT_FALSE(process_with_arg_exists(id2)) << "a process of the killed job is still there";
}

TEST(Durability, AJobRunningPastTheWallClockLimitIsStoppedAndFailsSayingWhy)
{
    // A job whose runner would take ~3 s, on a server that lets an attempt
    // run 1 s: stopped (SIGTERM; the fake runner obeys), failed with the
    // reason, not retried; the server goes on with the next job.
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--jobs", "1", "--max-job-seconds", "1"}, 0.3);
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = http(server.port(), "POST", "/v1/jobs", R"({"name": "too long"})");
    ASSERT_EQ(r.status, 201);
    const std::string id(r.json().at("id").as_string());
    const json::value done = poll_job(server.port(), id, is_final, std::chrono::milliseconds(20000));
    EXPECT_EQ(state_of(done), "failed") << json::serialize(done);
    EXPECT_NE(std::string(done.at("error").as_string()).find("longer than this server's limit of 1 s"), std::string::npos)
        << json::serialize(done);
    EXPECT_EQ(done.at("attempts").to_number<int>(), 1);
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(6));
}

TEST(Durability, SecondServerOnTheSameDataDirectoryRefusesToStart)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data");
    EXPECT_THROW(ServerProcess(tmp.path() / "data"), std::runtime_error);
    // Deleting files in the directory does not release it (the lock is on
    // the directory itself; a lock file could be deleted from under it).
    for (const auto& entry : fs::directory_iterator(tmp.path() / "data"))
        if (entry.is_regular_file() && entry.path().extension() == ".lock") fs::remove(entry.path());
    std::string log;
    EXPECT_EQ(exit_code_on(tmp.path() / "data", log), 3) << log;
    EXPECT_NE(log.find("another wiredem-server uses"), std::string::npos) << log;
    EXPECT_EQ(http(server.port(), "GET", "/v1/health").status, 200);
}

// What an interrupted clean-up leaves is swept at start: the work folder of
// an ended job (a kill -9 while it was being removed), and a folder no job
// names (between a DELETE's row and its folder). A job that gives up after
// its interrupted attempts leaves no work folder (it kept its checkpoints).
TEST(Durability, LeftoverWorkFoldersAreSweptAndAJobThatGivesUpLeavesNone)
{
    TempDir tmp;
    const fs::path data = tmp.path() / "data";
    std::string ended, gives_up;
    {
        ServerProcess server(data, {"--jobs", "1"}, 0.01);
        for (std::string* id : {&ended, &gives_up}) {
            const auto r = http(server.port(), "POST", "/v1/jobs", R"({"name": "swept"})");
            ASSERT_EQ(r.status, 201);
            *id = std::string(r.json().at("id").as_string());
            ASSERT_EQ(state_of(poll_job(server.port(), *id, is_final)), "succeeded");
        }
        ASSERT_EQ(server.terminate(), 0);
    }
    const std::string orphan = "0123456789abcdef01234567";
    for (const auto& id : {ended, gives_up, orphan}) {
        fs::create_directories(data / "jobs" / id / "work" / "out" / "tests");
        write_file(data / "jobs" / id / "work" / "out" / "tests" / "test_0.checkpoint.h5", "half removed");
    }
    // Interrupted in its 5th attempt: the next start is its 6th, one too many.
    const std::string forge = "sqlite3 '" + (data / "jobs.sqlite3").string()
                            + "' \"UPDATE jobs SET state = 'running', attempts = 5 WHERE id = '" + gives_up + "'\"";
    ASSERT_EQ(std::system(forge.c_str()), 0) << "needs the sqlite3 command";

    ServerProcess server(data, {"--jobs", "1"}, 0.01);
    const auto given_up = poll_job(server.port(), gives_up, is_final);
    EXPECT_EQ(state_of(given_up), "failed");
    EXPECT_NE(json::serialize(given_up).find("gave up after 5 interrupted attempts"), std::string::npos);
    for (int i = 0; i < 100 && fs::exists(data / "jobs" / gives_up / "work"); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_FALSE(fs::exists(data / "jobs" / gives_up / "work"));
    EXPECT_FALSE(fs::exists(data / "jobs" / ended / "work"));
    EXPECT_TRUE(fs::is_regular_file(data / "jobs" / ended / "result.h5"));
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + ended + "/summary").status, 200);
    EXPECT_FALSE(fs::exists(data / "jobs" / orphan));
}

// A full disk under the data directory: a submit is answered 507 with
// Retry-After (the store cannot take it), not 500, the server keeps
// answering, and once space is freed the same submit is taken. A real small
// tmpfs, mounted by the test (root or CAP_SYS_ADMIN; skipped where mount is
// refused: tests/io's WriteError cases inject the same full disk without a
// mount, and the route maps any io::WriteError alike).
TEST(Durability, AFullDiskIsAnswered507WithRetryAfterUntilSpaceIsFreed)
{
    TempDir tmp;
    const fs::path small = tmp.path() / "small";
    fs::create_directories(small);
    if (::mount("tmpfs", small.c_str(), "tmpfs", 0, "size=8m,mode=0700") != 0)
        GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
    struct Unmount {
        fs::path at;
        ~Unmount() { ::umount2(at.c_str(), MNT_DETACH); }
    } unmount{small};
    {
        ServerProcess server(small / "data", {"--jobs", "1"});
        const auto first = http(server.port(), "POST", "/v1/jobs", R"({"name": "before"})");
        ASSERT_EQ(first.status, 201) << first.body;
        poll_job(server.port(), std::string(first.json().at("id").as_string()), is_final);

        // Every byte taken.
        {
            std::ofstream filler(small / "filler", std::ios::binary);
            const std::string block(1 << 16, 'x');
            while (filler.write(block.data(), static_cast<std::streamsize>(block.size()))) {
            }
        }
        RawReply full;
        for (int k = 0; k < 20 && full.status != 507; ++k)  // the store's journal may hold a little room of its own
            full = http(server.port(), "POST", "/v1/jobs", R"({"name": "while full )" + std::to_string(k) + "\"}");
        EXPECT_EQ(full.status, 507) << full.body;
        EXPECT_EQ(full.error_code(), "insufficient_storage") << full.body;
        EXPECT_TRUE(full.headers.count("retry-after")) << full.body;
        EXPECT_NE(full.body.find("no space left on device"), std::string::npos) << full.body;
        EXPECT_EQ(http(server.port(), "GET", "/v1/health").status, 200);

        fs::remove(small / "filler");
        const auto after = http(server.port(), "POST", "/v1/jobs", R"({"name": "after"})");
        EXPECT_EQ(after.status, 201) << after.body;
        EXPECT_EQ(state_of(poll_job(server.port(), std::string(after.json().at("id").as_string()), is_final, std::chrono::seconds(40))), "succeeded")
            << server.log();
        EXPECT_EQ(server.terminate(), 0) << server.log();
    }
}

} // namespace
} // namespace wiredem::test

namespace wiredem::test {
namespace {

bool is_testing(const boost::json::value& j)
{
    const auto* stage = j.as_object().if_contains("stage");
    return stage && stage->is_string() && stage->as_string() == "testing";
}

/// summary.json without what says how a run went rather than what it computed.
boost::json::value computed_figures(const std::string& summary_text)
{
    boost::json::value v = boost::json::parse(summary_text);
    for (boost::json::value& t : v.at("tests").as_array()) {
        t.as_object().erase("wall_time_s");
        t.as_object().erase("threads");
    }
    v.at("engine").as_object().erase("wall_time_s");
    v.at("engine").as_object().erase("body_steps_per_second");
    v.at("engine").as_object().erase("threads");
    v.at("specimen").as_object().erase("preparation_wall_time_s");
    return v;
}

} // namespace

// With the real runner: kill -9 the server during a test. The runner, told by
// the kernel (SIGTERM on its parent's death), saves a checkpoint on its way
// out; the restarted server runs the job again in the same work folder, the
// runner continues from the specimen and the checkpoints, and the job ends
// with exactly the figures of a run never interrupted.
TEST(DurabilityRealRunner, AJobInterruptedByKillNineContinuesFromItsCheckpointsToTheSameResult)
{
    namespace fs = std::filesystem;
    TempDir tmp;
    const fs::path data = tmp.path() / "data";
    const fs::path tiny = fs::path(WIREDEM_SOURCE_DIR) / "examples/tiny.json";
    const auto reference = run_client({"run", tiny.string(), "-o", (tmp.path() / "ref").string(), "--threads", "1"});
    ASSERT_EQ(reference.exit_code, 0) << reference.err;

    const std::vector<std::string> args{"--runner", WIREDEM_CLIENT_BIN, "--jobs", "1", "--threads-per-job", "1",
        "--checkpoint-seconds", "0.05", "--max-steps-per-job", "1e8"};
    std::string id;
    {
        ServerProcess server(data, args);
        const auto r = http(server.port(), "POST", "/v1/jobs", read_file(tiny));
        ASSERT_EQ(r.status, 201) << r.body;
        id = std::string(r.json().at("id").as_string());
        ASSERT_TRUE(is_testing(poll_job(server.port(), id, is_testing, std::chrono::seconds(60)))) << server.log();
        std::this_thread::sleep_for(std::chrono::milliseconds(300)); // into the test
        server.kill_hard();
    }
    const fs::path work = data / "jobs" / id / "work";
    for (int i = 0; i < 250 && process_with_arg_exists(work.string()); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_FALSE(process_with_arg_exists(work.string()));
    EXPECT_TRUE(fs::exists(work / "out/specimen.h5"));
    EXPECT_TRUE(fs::exists(work / "out/tests/test_0.checkpoint.h5") || fs::exists(work / "out/tests/test_0.h5"))
        << "the interrupted runner left nothing to continue from";

    ServerProcess restarted(data, args);
    const auto job = poll_job(restarted.port(), id, is_final, std::chrono::seconds(120));
    ASSERT_EQ(state_of(job), "succeeded") << restarted.log();
    EXPECT_EQ(job.at("attempts").to_number<int>(), 2);
    EXPECT_EQ(computed_figures(read_file(data / "jobs" / id / "summary.json")),
        computed_figures(read_file(tmp.path() / "ref/summary.json")));
}

} // namespace wiredem::test
