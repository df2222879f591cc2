// Issue 18, items 7 and 9: a store that does not grow without bound (DELETE
// of ended jobs with their files, a retention bound), a data directory whose
// planted symlinks redirect no download and no write, files other users
// cannot read, and idle connections that cannot lock other clients out.
#include "harness.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <thread>

namespace wiredem::test {
namespace {
namespace fs = std::filesystem;
namespace json = boost::json;
using namespace std::chrono_literals;

bool is_final(const json::value& j)
{
    const auto s = state_of(j);
    return s == "succeeded" || s == "failed" || s == "cancelled";
}

/// POSTs a job named `name`; returns its id.
std::string submit(std::uint16_t port, const std::string& name)
{
    const auto r = http(port, "POST", "/v1/jobs", R"({"name": ")" + name + R"("})");
    EXPECT_EQ(r.status, 201) << r.body;
    return r.status == 201 ? std::string(r.json().at("id").as_string()) : std::string();
}

/// A connection to the server that sends `bytes` (maybe none) and stays open.
class HeldConnection {
public:
    HeldConnection(std::uint16_t port, const std::string& bytes = {})
    {
        fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_port = htons(port);
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        if (::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) ADD_FAILURE() << "connect";
        if (!bytes.empty() && ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) < 0) ADD_FAILURE() << "send";
    }
    ~HeldConnection() { ::close(fd_); }
    HeldConnection(const HeldConnection&) = delete;
    HeldConnection& operator=(const HeldConnection&) = delete;

    /// Whether the server closed it (end of file or reset) within `limit`.
    bool closed_within(std::chrono::milliseconds limit) const
    {
        pollfd p{fd_, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(limit.count())) <= 0) return false;
        char c;
        return ::recv(fd_, &c, 1, MSG_DONTWAIT) <= 0;
    }

private:
    int fd_ = -1;
};

mode_t mode_of(const fs::path& p)
{
    struct stat st{};
    EXPECT_EQ(::stat(p.c_str(), &st), 0) << p;
    return st.st_mode & 07777;
}

TEST(Retention, DeleteWithRemoveDeletesAnEndedJobWithItsFilesAndOnlyThen)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {}, 0.2);
    const std::string id = submit(server.port(), "to delete");
    ASSERT_EQ(state_of(poll_job(server.port(), id, is_final)), "succeeded");
    const fs::path folder = tmp.path() / "data" / "jobs" / id;
    ASSERT_TRUE(fs::exists(folder / "result.h5"));
    // A plain DELETE is a cancel: it never deletes results (a cancel that
    // crosses the job's success must not).
    EXPECT_EQ(http(server.port(), "DELETE", "/v1/jobs/" + id).error_code(), "already_finished");
    EXPECT_EQ(http(server.port(), "DELETE", "/v1/jobs/" + id + "?remove=yes").status, 400);
    const auto removed = http(server.port(), "DELETE", "/v1/jobs/" + id + "?remove=true");
    EXPECT_EQ(removed.status, 204);
    EXPECT_TRUE(removed.body.empty());
    EXPECT_FALSE(fs::exists(folder)) << "its files go with it";
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + id).status, 404);
    EXPECT_EQ(http(server.port(), "DELETE", "/v1/jobs/" + id + "?remove=true").status, 404);

    // A running job is not removed; cancelled (twice, harmlessly), it can be.
    const std::string slow = submit(server.port(), "slow to cancel");
    EXPECT_EQ(http(server.port(), "DELETE", "/v1/jobs/" + slow + "?remove=true").error_code(), "not_finished");
    EXPECT_EQ(http(server.port(), "DELETE", "/v1/jobs/" + slow).status, 200);
    const auto again = http(server.port(), "DELETE", "/v1/jobs/" + slow);
    EXPECT_EQ(again.status, 200);
    EXPECT_EQ(state_of(again.json()), "cancelled");
    EXPECT_EQ(http(server.port(), "DELETE", "/v1/jobs/" + slow + "?remove=true").status, 204);
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + slow).status, 404);
}

TEST(Retention, OnlyTheNewestEndedJobsAreKeptWithTheirFiles)
{
    // Submitted and cancelled at once, jobs used to count against no limit.
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--max-finished-jobs", "2"}, 0.2);
    const std::string running = submit(server.port(), "slow, holds the worker");
    std::vector<std::string> ended;
    for (int i = 0; i < 4; ++i) {
        ended.push_back(submit(server.port(), "cancelled " + std::to_string(i)));
        ASSERT_EQ(http(server.port(), "DELETE", "/v1/jobs/" + ended.back()).status, 200);
    }
    (void)submit(server.port(), "the next submit applies the bound");
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + ended[0]).status, 404);
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + ended[1]).status, 404);
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + ended[2]).status, 200);
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + ended[3]).status, 200);
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + running).status, 200) << "a job that has not ended stays";
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs?state=cancelled").json().at("jobs").as_array().size(), 2u);
}

TEST(DataDirectory, APlantedSymlinkRedirectsNoDownload)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data");
    const std::string id = submit(server.port(), "downloaded");
    ASSERT_EQ(state_of(poll_job(server.port(), id, is_final)), "succeeded");
    const fs::path jobs = tmp.path() / "data" / "jobs";
    // Another folder with files of the same names, and the job's folder a
    // symlink to it: neither file may be served from there.
    const fs::path elsewhere = tmp.path() / "elsewhere";
    fs::create_directories(elsewhere);
    write_file(elsewhere / "summary.json", R"({"secret": "not the job's"})");
    write_file(elsewhere / "result.h5", "not the job's either");
    write_file(elsewhere / "result.xdmf", "<Xdmf>not the job's</Xdmf>");
    fs::rename(jobs / id, tmp.path() / "moved");
    fs::create_directory_symlink(elsewhere, jobs / id);
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + id + "/summary").status, 500);
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + id + "/result.h5").status, 500);
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + id + "/result.xdmf").status, 404);  // the result data routes too
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + id + "/tests").status, 500);
    // The folder back, its summary a symlink: not followed either.
    fs::remove(jobs / id);
    fs::rename(tmp.path() / "moved", jobs / id);
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + id + "/summary").status, 200);
    fs::remove(jobs / id / "summary.json");
    fs::create_symlink(elsewhere / "summary.json", jobs / id / "summary.json");
    const auto summary = http(server.port(), "GET", "/v1/jobs/" + id + "/summary");
    EXPECT_EQ(summary.status, 500);
    EXPECT_EQ(summary.body.find("secret"), std::string::npos);
}

TEST(DataDirectory, APlantedSymlinkRedirectsNoWrite)
{
    // A queued job's folder planted as a symlink before it runs: the job
    // fails saying so, and nothing is written where the link points.
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {}, 0.2);
    const std::string first = submit(server.port(), "slow, holds the worker");
    const std::string planted = submit(server.port(), "planted");
    const fs::path elsewhere = tmp.path() / "elsewhere";
    fs::create_directories(elsewhere);
    fs::create_directory_symlink(elsewhere, tmp.path() / "data" / "jobs" / planted);
    const auto job = poll_job(server.port(), planted, is_final, 30s);
    EXPECT_EQ(state_of(job), "failed");
    EXPECT_NE(std::string(job.at("error").as_string()).find("symbolic link"), std::string::npos) << job;
    EXPECT_TRUE(fs::is_empty(elsewhere)) << "the runner's files went through the link";
    EXPECT_EQ(state_of(poll_job(server.port(), first, is_final, 30s)), "succeeded");
}

TEST(DataDirectory, OtherUsersCannotReadTheStoreOrTheResults)
{
    for (const bool with_token : {false, true}) {
        TempDir tmp;
        std::vector<std::string> args;
        std::vector<std::pair<std::string, std::string>> auth;
        if (with_token) {
            write_file(tmp.path() / "token", "s3cret-token\n");  // 0644: said in the log
            args = {"--token-file", (tmp.path() / "token").string()};
            auth = {{"Authorization", "Bearer s3cret-token"}};
        }
        ServerProcess server(tmp.path() / "data", args);
        const auto posted = http(server.port(), "POST", "/v1/jobs", R"({"name": "private"})", auth);
        ASSERT_EQ(posted.status, 201);
        const std::string id(posted.json().at("id").as_string());
        ASSERT_EQ(state_of(poll_job(server.port(), id, is_final, 20s, with_token ? "s3cret-token" : "")), "succeeded");
        // Nothing for others; nothing for the group either with a token.
        const mode_t closed = with_token ? 077 : 007;
        for (const fs::path& p : {tmp.path() / "data", tmp.path() / "data" / "jobs.sqlite3",
                 tmp.path() / "data" / "jobs" / id, tmp.path() / "data" / "jobs" / id / "result.h5",
                 tmp.path() / "data" / "jobs" / id / "summary.json"})
            EXPECT_EQ(mode_of(p) & closed, 0u) << p << " mode " << std::oct << mode_of(p);
        if (with_token) {
            EXPECT_NE(server.log().find("may be read by other users (mode 0644)"), std::string::npos) << server.log();
        }
    }
}

// A runner's grandchild that leaves the runner's process group (setsid)
// and outlives it is killed with it: the server is the subreaper of its
// runners' descendants and kills the orphans carrying the runner's tag
// (child_process.hpp). Before, it went to init and ran on.
TEST(Runners, ADescendantThatLeftTheProcessGroupIsKilledWithItsRunner)
{
    TempDir tmp;
    const fs::path pid_file = tmp.path() / "escaped.pid";
    const fs::path runner = tmp.path() / "escaping_runner.sh";
    write_file(runner, "#!/bin/sh\n"
                       "setsid sh -c 'echo $$ > \"" + pid_file.string() + ".tmp\"; mv \"" + pid_file.string() + ".tmp\" \""
                           + pid_file.string() + "\"; exec sleep 300' </dev/null >/dev/null 2>&1 &\n"
                       "while [ ! -s \"" + pid_file.string() + "\" ]; do sleep 0.05; done\n"
                       "echo 'runner: gave up, leaving a daemon behind' >&2\n"
                       "exit 1\n");
    fs::permissions(runner, fs::perms::owner_all);
    ServerProcess server(tmp.path() / "data", {"--runner", runner.string(), "--jobs", "1"});
    const std::string id = submit(server.port(), "escaping");
    const auto job = poll_job(server.port(), id, is_final);
    EXPECT_EQ(state_of(job), "failed");
    ASSERT_TRUE(fs::exists(pid_file));
    const pid_t escaped = static_cast<pid_t>(std::stol(read_file(pid_file)));
    bool gone = false;
    for (int i = 0; i < 100 && !gone; ++i) {
        gone = ::kill(escaped, 0) != 0;
        if (!gone) std::this_thread::sleep_for(20ms);
    }
    EXPECT_TRUE(gone) << "pid " << escaped << " outlived its runner";
    if (!gone) ::kill(escaped, SIGKILL);
}

TEST(Connections, IdleConnectionsCannotLockOthersOut)
{
    // As many idle connections as the server takes, opened before anything
    // else: a client that then connects is served at once — the longest
    // idle connection is closed to make room — instead of waiting for the
    // read timeout or being dropped.
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--max-connections", "8", "--idle-timeout", "60"});
    std::vector<std::unique_ptr<HeldConnection>> idle;
    for (int i = 0; i < 8; ++i) idle.push_back(std::make_unique<HeldConnection>(server.port()));
    std::this_thread::sleep_for(200ms);  // all accepted
    const auto t0 = std::chrono::steady_clock::now();
    const auto health = http(server.port(), "GET", "/v1/health");
    EXPECT_EQ(health.status, 200);
    EXPECT_LT(std::chrono::steady_clock::now() - t0, 2s);
    EXPECT_TRUE(idle.front()->closed_within(2000ms)) << "the longest idle connection made room";
}

// Connections that each send a byte (or part of their headers) and stall
// held every place for the read timeout, and newcomers heard 503 until
// then: until its headers are in, a connection is given up for a newcomer
// as an idle one is.
TEST(Connections, ConnectionsThatSendAByteCannotLockOthersOut)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--max-connections", "8", "--read-timeout", "60"});
    std::vector<std::unique_ptr<HeldConnection>> stalled;
    for (int i = 0; i < 8; ++i) {
        stalled.push_back(std::make_unique<HeldConnection>(server.port(), i % 2 ? "G" : "GET /v1/health HTTP/1.1\r\nHo"));
        std::this_thread::sleep_for(20ms);  // in order: the first is the oldest
    }
    std::this_thread::sleep_for(200ms);
    const auto t0 = std::chrono::steady_clock::now();
    const auto health = http(server.port(), "GET", "/v1/health");
    EXPECT_EQ(health.status, 200) << health.body;
    EXPECT_LT(std::chrono::steady_clock::now() - t0, 2s);
    EXPECT_TRUE(stalled.front()->closed_within(2000ms)) << "the oldest stalled connection made room";
}

TEST(Connections, WhenEveryConnectionIsBusyANewcomerHearsSo)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--max-connections", "4", "--read-timeout", "30"});
    std::vector<std::unique_ptr<HeldConnection>> busy;
    for (int i = 0; i < 4; ++i)  // each with its headers in, in the middle of its body
        busy.push_back(std::make_unique<HeldConnection>(server.port(),
            "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: 100\r\n\r\n{"));
    std::this_thread::sleep_for(300ms);
    const auto refused = http(server.port(), "GET", "/v1/health");
    EXPECT_EQ(refused.status, 503);
    EXPECT_EQ(refused.error_code(), "too_many_connections");
    EXPECT_EQ(refused.headers.count("retry-after"), 1u);
    busy.clear();  // they go; room again
    std::this_thread::sleep_for(300ms);
    EXPECT_EQ(http(server.port(), "GET", "/v1/health").status, 200);
}

TEST(Connections, AConnectionThatSendsNothingIsClosedAfterTheIdleTimeout)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--idle-timeout", "1", "--read-timeout", "30"});
    HeldConnection silent(server.port());
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_TRUE(silent.closed_within(4000ms));
    EXPECT_GT(std::chrono::steady_clock::now() - t0, 800ms);
    // A request begun is given the read timeout, not the idle one.
    HeldConnection slow(server.port(), "GET /v1/health HTTP/1.1\r\n");
    EXPECT_FALSE(slow.closed_within(2500ms));
}

} // namespace
} // namespace wiredem::test
