// `wiredem-server --executor slurm` on a real single-node Slurm cluster
// (scripts/slurm-cluster.sh, started and stopped by tests/slurm/run.sh, which
// exports SLURM_CONF): the real `wiredem` runs the stages of tiny campaigns
// as Slurm jobs.
//
// - The same study through Slurm and through the local executor gives the
//   same summary, bit for bit, though the Slurm server is killed (kill -9)
//   while the study runs and a new one re-attaches to the Slurm jobs in the
//   store: each job is submitted once (three Slurm jobs, counted by squeue).
// - A point whose test stage fails (a wiredem that exits 1 for it) fails
//   with that stage's stderr, the other point succeeds; a job sbatch refuses
//   fails with sbatch's message; a cancelled study leaves no Slurm job
//   pending or running.
#include "../server/harness.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <cstdio>
#include <set>
#include <thread>

namespace wiredem::test {
namespace {
namespace fs = std::filesystem;
namespace json = boost::json;
using clock_type = std::chrono::steady_clock;

/// examples/tiny.json, loaded to half its strain (the test is about the
/// plumbing, and its time is CI's), with a helix that fits its 8 mm
/// membrane when a point asks for one.
json::value tiny()
{
    json::value t = json::parse(read_file(fs::path(WIREDEM_SOURCE_DIR) / "examples/tiny.json"));
    t.at("specimen").at("wire").as_object()["helix_radius_m"] = 0.005;
    t.at("triaxial").as_object()["target_axial_strain"] = 0.04;
    t.at("triaxial").as_object()["snapshot_strains"] = json::array{0, 0.04};
    return t;
}

std::string study_text(const std::string& name, json::object vary)
{
    return json::serialize(json::object{{"name", name}, {"base", tiny()}, {"vary", std::move(vary)}});
}

/// The output of a command line of the test's own making (no outside text).
std::string command_output(const std::string& command)
{
    std::string out;
    FILE* p = ::popen(command.c_str(), "r");
    if (!p) return out;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, p)) out.append(buf, n);
    ::pclose(p);
    return out;
}

/// Slurm's jobs named for a wiredem job, every state Slurm still holds: job
/// (or array) id → states of its lines.
std::map<std::string, std::vector<std::string>> slurm_jobs_of(const std::string& job_id)
{
    std::map<std::string, std::vector<std::string>> jobs;
    std::istringstream in(command_output("squeue --noheader --array --states=all --name=wiredem-" + job_id
                                         + " --format='%F|%T'"));
    for (std::string line; std::getline(in, line);) {
        const auto bar = line.find('|');
        if (bar != std::string::npos) jobs[line.substr(0, bar)].push_back(line.substr(bar + 1));
    }
    return jobs;
}

json::value get_study(std::uint16_t port, const std::string& id) { return http(port, "GET", "/v1/studies/" + id).json(); }

std::vector<std::string> job_ids_of(const json::value& study)
{
    std::vector<std::string> ids;
    for (const auto& p : study.at("jobs").as_array()) ids.emplace_back(p.at("job").at("id").as_string());
    return ids;
}

/// Polls until `pred` holds (at most `limit`); false when it never did.
template <class Pred>
bool wait_for(Pred pred, std::chrono::seconds limit)
{
    const auto until = clock_type::now() + limit;
    while (clock_type::now() < until) {
        if (pred()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    return pred();
}

bool all_ended(std::uint16_t port, const std::string& study_id)
{
    const json::value s = get_study(port, study_id);
    const auto& c = s.at("jobs_by_state");
    return c.at("queued").to_number<int>() + c.at("preparing").to_number<int>() + c.at("running").to_number<int>() == 0;
}

/// The study's summary as fetched, without what differs between servers (ids).
json::value fetched_summary(const std::string& url, const std::string& study_id, const fs::path& dir)
{
    const auto fetched = run_client({"study", "fetch", study_id, "-o", dir.string(), "--server", url});
    EXPECT_EQ(fetched.exit_code, 0) << fetched.err;
    json::value s = json::parse(read_file(dir / "summary.json"));
    s.as_object().erase("id");
    for (json::value& p : s.at("points").as_array()) p.as_object().erase("job_id");
    return s;
}

std::vector<std::string> slurm_server_args(std::vector<std::string> more)
{
    std::vector<std::string> args{"--runner", WIREDEM_CLIENT_BIN, "--executor", "slurm", "--jobs", "4",
        "--slurm-cpus-per-task", "1", "--slurm-poll-seconds", "0.3", "--slurm-time-limit", "10",
        "--max-steps-per-job", "1e8"};
    args.insert(args.end(), more.begin(), more.end());
    return args;
}

} // namespace

TEST(SlurmCluster, AStudyThroughSlurmGivesTheLocalSummaryAndARestartedServerFollowsItsSlurmJobs)
{
    TempDir tmp;
    const std::string study = study_text("patterns", {{"specimen.wire.pattern", json::array{"none", "helix"}},
                                                         {"seed", json::array{1, 2}}});
    write_file(tmp.path() / "study.json", study);

    std::string local_id;
    json::value local;
    {
        ServerProcess server(tmp.path() / "local",
            {"--runner", WIREDEM_CLIENT_BIN, "--jobs", "2", "--threads-per-job", "1", "--max-steps-per-job", "1e8"});
        const auto r = run_client({"study", "submit", (tmp.path() / "study.json").string(), "--wait", "--interval",
            "0.2", "--server", server.url()});
        ASSERT_EQ(r.exit_code, 0) << r.err << server.log();
        local_id = r.out.substr(0, r.out.find('\n'));
        local = fetched_summary(server.url(), local_id, tmp.path() / "local-fetched");
    }

    const fs::path data = tmp.path() / "slurm";
    std::string id;
    std::vector<std::string> jobs;
    std::map<std::string, json::value> slurm_ids;
    {
        ServerProcess server(data, slurm_server_args({}));
        const auto r = http(server.port(), "POST", "/v1/studies", study);
        ASSERT_EQ(r.status, 201) << r.body;
        id = std::string(r.json().at("id").as_string());
        jobs = job_ids_of(get_study(server.port(), id));
        ASSERT_EQ(jobs.size(), 4u);
        // Every job submitted (its Slurm ids in GET /v1/jobs/{id}), then the server dies.
        ASSERT_TRUE(wait_for(
            [&] {
                for (const auto& j : jobs)
                    if (!http(server.port(), "GET", "/v1/jobs/" + j).json().as_object().contains("slurm")) return false;
                return true;
            },
            std::chrono::seconds(30)))
            << server.log();
        for (const auto& j : jobs) slurm_ids[j] = http(server.port(), "GET", "/v1/jobs/" + j).json().at("slurm");
        EXPECT_FALSE(all_ended(server.port(), id)) << "the study ended before the restart: nothing was re-attached";
        server.kill_hard();
    }
    // Its jobs are in Slurm: a server that would run them here refuses to start.
    std::string refused;
    EXPECT_EQ(server_exit_code(data, {"--executor", "local"}, refused), 3) << refused;
    EXPECT_NE(refused.find("were submitted to Slurm: start the server with --executor slurm"), std::string::npos)
        << refused;
    ServerProcess server(data, slurm_server_args({}));
    ASSERT_TRUE(wait_for([&] { return all_ended(server.port(), id); }, std::chrono::seconds(240))) << server.log();
    const json::value there = fetched_summary(server.url(), id, tmp.path() / "slurm-fetched");
    EXPECT_EQ(json::serialize(local), json::serialize(there));
    EXPECT_EQ(there.at("groups").as_array().at(0).at("succeeded").to_number<int>(), 2) << server.log();

    for (const auto& j : jobs) {
        const json::value job = http(server.port(), "GET", "/v1/jobs/" + j).json();
        EXPECT_EQ(job.at("state"), "succeeded") << job;
        // The store's Slurm ids are those submitted before the restart, and
        // Slurm holds exactly three jobs for it: nothing was submitted twice.
        EXPECT_EQ(job.at("slurm"), slurm_ids[j]);
        const auto in_slurm = slurm_jobs_of(j);
        EXPECT_EQ(in_slurm.size(), 3u) << j;
        for (const char* key : {"prepare_job_id", "test_array_job_id", "analyse_job_id"})
            EXPECT_TRUE(in_slurm.count(std::to_string(job.at("slurm").at(key).to_number<std::int64_t>()))) << key;
        const auto tests = in_slurm.find(std::to_string(job.at("slurm").at("test_array_job_id").to_number<std::int64_t>()));
        ASSERT_NE(tests, in_slurm.end());
        EXPECT_EQ(tests->second, (std::vector<std::string>{"COMPLETED", "COMPLETED"}));
        EXPECT_FALSE(fs::exists(data / "jobs" / j / "work")) << "the work folder outlived its published results";
    }
    EXPECT_NE(server.log().find("following its Slurm jobs"), std::string::npos) << server.log();
}

TEST(SlurmCluster, AFailingStageFailsItsPointAloneAndACancelledStudyLeavesNoSlurmJob)
{
    TempDir tmp;
    // A wiredem whose test stage fails for the point that asks for it (its
    // comment), as a broken node or a crashing test would.
    const fs::path wrapper = tmp.path() / "wiredem-failing-a-test";
    write_file(wrapper, std::string("#!/bin/sh\n"
                                    "if [ \"$1\" = test ] && grep -q fail-this-point \"$2/job.json\"; then\n"
                                    "  echo 'wiredem: test stage broken on purpose' >&2; exit 1\n"
                                    "fi\n"
                                    "exec '") + WIREDEM_CLIENT_BIN + "' \"$@\"\n");
    fs::permissions(wrapper, fs::perms::owner_all);
    ServerProcess server(tmp.path() / "data", slurm_server_args({"--slurm-wiredem", wrapper.string()}));

    auto r = http(server.port(), "POST", "/v1/studies",
        study_text("one-fails", {{"comment", json::array{"fine", "fail-this-point"}}}));
    ASSERT_EQ(r.status, 201) << r.body;
    const std::string failing_study(r.json().at("id").as_string());
    ASSERT_TRUE(wait_for([&] { return all_ended(server.port(), failing_study); }, std::chrono::seconds(180)))
        << server.log();
    const json::value s = get_study(server.port(), failing_study);
    const auto& points = s.at("jobs").as_array();
    EXPECT_EQ(points.at(0).at("job").at("state"), "succeeded") << s;
    const json::value failed = http(server.port(), "GET", "/v1/jobs/" + std::string(points.at(1).at("job").at("id").as_string())).json();
    EXPECT_EQ(failed.at("state"), "failed") << failed;
    const std::string error(failed.at("error").as_string());
    const std::string array = std::to_string(failed.at("slurm").at("test_array_job_id").to_number<std::int64_t>());
    // Both of the point's tests fail, each in its own array task: the job
    // fails with whichever Slurm reports first, named with its own task.
    const bool first = error.find("test 1 of 2 (Slurm job " + array + "_0) FAILED") != std::string::npos;
    const bool second = error.find("test 2 of 2 (Slurm job " + array + "_1) FAILED") != std::string::npos;
    EXPECT_TRUE(first != second) << error;
    EXPECT_NE(error.find("wiredem: test stage broken on purpose"), std::string::npos) << error;

    // A job that sbatch refuses (a partition the cluster does not have) fails with sbatch's word.
    {
        ServerProcess refused(tmp.path() / "refused", slurm_server_args({"--slurm-partition", "nope"}));
        const auto posted = http(refused.port(), "POST", "/v1/jobs", json::serialize(tiny()));
        ASSERT_EQ(posted.status, 201) << posted.body;
        const json::value job = poll_job(refused.port(), std::string(posted.json().at("id").as_string()),
            [](const json::value& j) { return state_of(j) == "failed"; });
        EXPECT_EQ(state_of(job), "failed") << job;
        EXPECT_NE(job.at("error").as_string().find("sbatch failed (exited with status 1): sbatch: error: invalid partition"),
            std::string::npos)
            << job;
    }

    // A study cancelled while its jobs are in Slurm.
    r = http(server.port(), "POST", "/v1/studies", study_text("cancelled", {{"seed", json::array{3, 4}}}));
    ASSERT_EQ(r.status, 201) << r.body;
    const std::string cancelled_study(r.json().at("id").as_string());
    const auto jobs = job_ids_of(get_study(server.port(), cancelled_study));
    ASSERT_TRUE(wait_for([&] { return !slurm_jobs_of(jobs.at(0)).empty() && !slurm_jobs_of(jobs.at(1)).empty(); },
        std::chrono::seconds(30)))
        << server.log();
    EXPECT_EQ(http(server.port(), "DELETE", "/v1/studies/" + cancelled_study).status, 200);
    ASSERT_TRUE(wait_for([&] { return all_ended(server.port(), cancelled_study); }, std::chrono::seconds(30)));
    const auto active = [&] {
        std::size_t n = 0;
        for (const auto& j : jobs)
            for (const auto& [slurm_id, states] : slurm_jobs_of(j))
                for (const auto& st : states) n += st == "PENDING" || st == "RUNNING" || st == "COMPLETING";
        return n;
    };
    EXPECT_TRUE(wait_for([&] { return active() == 0; }, std::chrono::seconds(30))) << command_output("squeue");
    for (const auto& j : jobs) {
        EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + j).json().at("state"), "cancelled");
        EXPECT_TRUE(wait_for([&] { return !fs::exists(tmp.path() / "data/jobs" / j / "work"); }, std::chrono::seconds(40)));
    }
}

} // namespace wiredem::test
