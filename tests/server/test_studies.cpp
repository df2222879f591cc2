// Parameter studies through the server (/v1/studies) and the client's
// `study` commands, with the fake runner: a study creates a job per point,
// summarises them with the spread over seeds, cancels together, reports a
// failing point without stopping the others, and hostile documents get
// clear errors with nothing created.
#include "harness.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <thread>

namespace wiredem::test {
namespace {
namespace fs = std::filesystem;
namespace json = boost::json;

json::value tiny()
{
    return json::parse(read_file(fs::path(WIREDEM_SOURCE_DIR) / "examples/tiny.json"));
}

std::string study_text(const std::string& name, json::object vary)
{
    return json::serialize(json::object{{"name", name}, {"base", tiny()}, {"vary", std::move(vary)}});
}

/// Polls the study until `pred` holds (at most 30 s); returns it.
json::value poll_study(std::uint16_t port, const std::string& id, bool (*pred)(const json::value&))
{
    json::value s;
    for (int i = 0; i < 600; ++i) {
        s = http(port, "GET", "/v1/studies/" + id).json();
        if (pred(s)) return s;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return s;
}

std::int64_t count(const json::value& study, const char* state)
{
    return study.at("jobs_by_state").at(state).to_number<std::int64_t>();
}

bool all_ended(const json::value& s)
{
    return count(s, "queued") + count(s, "preparing") + count(s, "running") == 0;
}

} // namespace

TEST(Studies, AStudyCreatesAJobPerPointAndSummarisesThemOverTheSeeds)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--jobs", "2"}, 0.01);
    const auto r = http(server.port(), "POST", "/v1/studies",
        study_text("seeds", {{"comment", json::array{"a", "fail-this-point b"}}, {"seed", json::array{1, 2, 3}}}));
    ASSERT_EQ(r.status, 201) << r.body;
    const std::string id(r.json().at("id").as_string());
    EXPECT_EQ(r.headers.at("location"), "/v1/studies/" + id);
    EXPECT_EQ(r.json().at("points").to_number<int>(), 6);

    const json::value s = poll_study(server.port(), id, all_ended);
    ASSERT_TRUE(all_ended(s)) << json::serialize(s);
    // The three points whose comment asks for a failure failed; the others ran.
    EXPECT_EQ(count(s, "succeeded"), 3) << json::serialize(s);
    EXPECT_EQ(count(s, "failed"), 3) << json::serialize(s);
    const json::array& jobs = s.at("jobs").as_array();
    ASSERT_EQ(jobs.size(), 6u);
    EXPECT_EQ(jobs[4].at("label"), "comment=\"fail-this-point b\" seed=2");
    EXPECT_EQ(jobs[4].at("values").at("seed").to_number<int>(), 2);
    // Every point is an ordinary job, listed with the others.
    const std::string job0(jobs[0].at("job").at("id").as_string());
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + job0).status, 200);

    const json::value sum = http(server.port(), "GET", "/v1/studies/" + id + "/summary").json();
    const json::array& groups = sum.at("groups").as_array();
    ASSERT_EQ(groups.size(), 2u) << json::serialize(sum);
    EXPECT_EQ(groups[0].at("succeeded").to_number<int>(), 3);
    EXPECT_EQ(groups[0].at("friction_angle_deg").at("mean").to_number<double>(), 41.25); // the fake runner's φ
    EXPECT_EQ(groups[0].at("friction_angle_deg").at("sd").to_number<double>(), 0.0);
    EXPECT_EQ(groups[1].at("succeeded").to_number<int>(), 0);
    EXPECT_TRUE(groups[1].at("friction_angle_deg").at("mean").is_null());
    const json::value& failed = sum.at("points").as_array()[3];
    EXPECT_EQ(failed.at("state"), "failed");
    EXPECT_NE(std::string(failed.at("error").as_string()).find("collapsed"), std::string::npos) << json::serialize(failed);

    // The list, and the client's commands on the same study.
    const json::value list = http(server.port(), "GET", "/v1/studies?limit=5").json();
    EXPECT_EQ(json::value_to<std::string>(list.at("studies").as_array().at(0).at("id")), id);
    const auto table = run_client({"study", "summary", id, "--server", server.url()});
    EXPECT_EQ(table.exit_code, 0) << table.err;
    EXPECT_NE(table.out.find("41.2 ± 0.0 (3)"), std::string::npos) << table.out;
    const auto csv = run_client({"study", "summary", id, "--csv", "--server", server.url()});
    EXPECT_NE(csv.out.find("index,comment,seed,state,job_id,friction_angle_deg"), std::string::npos) << csv.out;
    const auto fetched = run_client({"study", "fetch", id, "-o", (tmp.path() / "f").string(), "--server", server.url()});
    EXPECT_EQ(fetched.exit_code, 0) << fetched.err;
    EXPECT_TRUE(fs::exists(tmp.path() / "f/points/0/result.h5"));
    EXPECT_FALSE(fs::exists(tmp.path() / "f/points/3")); // failed: nothing to fetch
    EXPECT_EQ(read_file(tmp.path() / "f/summary.json"),
        http(server.port(), "GET", "/v1/studies/" + id + "/summary").body); // as the server sent it
    const auto waited = run_client({"study", "wait", id, "--server", server.url()});
    EXPECT_EQ(waited.exit_code, 1) << waited.out << waited.err; // ended, not all succeeded: the job_failed code
}

TEST(Studies, CancellingAStudyCancelsEveryJobThatHasNotEnded)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--jobs", "1"}, 0.2);
    const auto r = http(server.port(), "POST", "/v1/studies", study_text("slow-study", {{"seed", json::array{1, 2, 3, 4}}}));
    ASSERT_EQ(r.status, 201) << r.body;
    const std::string id(r.json().at("id").as_string());
    poll_study(server.port(), id, [](const json::value& s) { return count(s, "preparing") + count(s, "running") > 0; });
    const auto c = run_client({"study", "cancel", id, "--server", server.url()});
    EXPECT_EQ(c.exit_code, 0) << c.err;
    const json::value s = poll_study(server.port(), id, all_ended);
    EXPECT_EQ(count(s, "cancelled"), 4) << json::serialize(s);
}

// A study whose jobs have all ended is deleted with them and their folders
// (DELETE ?remove=true, `wiredem study delete`), not before; and its jobs
// count towards --max-finished-jobs: once the study's oldest job is beyond
// the bound, the study goes whole.
TEST(Studies, AnEndedStudyIsDeletedWholeByRequestOrByTheRetentionBound)
{
    TempDir tmp;
    const fs::path data = tmp.path() / "data";
    ServerProcess server(data, {"--jobs", "1", "--max-finished-jobs", "3"}, 0.05);
    const auto submit = [&](const std::string& name) {
        const auto r = http(server.port(), "POST", "/v1/studies", study_text(name, {{"seed", json::array{1, 2}}}));
        EXPECT_EQ(r.status, 201) << r.body;
        return std::string(r.json().at("id").as_string());
    };
    const auto job_ids = [&](const std::string& id) {
        std::vector<std::string> ids;
        const json::value study = http(server.port(), "GET", "/v1/studies/" + id).json();
        for (const auto& p : study.at("jobs").as_array())
            ids.emplace_back(p.at("job").at("id").as_string());
        return ids;
    };

    const std::string first = submit("deleted");
    const auto first_jobs = job_ids(first);
    const auto early = http(server.port(), "DELETE", "/v1/studies/" + first + "?remove=true");
    EXPECT_EQ(early.status, 409) << early.body;
    EXPECT_EQ(early.error_code(), "not_finished");
    poll_study(server.port(), first, all_ended);
    EXPECT_EQ(http(server.port(), "DELETE", "/v1/studies/" + first + "?remove=false").status, 400);
    const auto c = run_client({"study", "delete", first, "--server", server.url()});
    EXPECT_EQ(c.exit_code, 0) << c.err;
    EXPECT_EQ(http(server.port(), "GET", "/v1/studies/" + first).status, 404);
    for (const auto& job : first_jobs) {
        EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + job).status, 404);
        EXPECT_FALSE(fs::exists(data / "jobs" / job));
    }
    EXPECT_EQ(http(server.port(), "GET", "/v1/studies").json().at("studies").as_array().size(), 0u);

    // Retention: the study's two jobs end first, then two jobs; the third
    // job's submit finds four ended jobs, the oldest the study's.
    const std::string kept = submit("retained");
    const auto kept_jobs = job_ids(kept);
    poll_study(server.port(), kept, all_ended);
    std::vector<std::string> later;
    for (int k = 0; k < 3; ++k) {
        std::string body = R"({"name": "later)";  // appended: GCC 12's -Warray-bounds misfires on "literal" + std::string
        body += std::to_string(k) + "\"}";
        const auto r = http(server.port(), "POST", "/v1/jobs", body);
        ASSERT_EQ(r.status, 201) << r.body;
        later.emplace_back(r.json().at("id").as_string());
        EXPECT_EQ(http(server.port(), "GET", "/v1/studies/" + kept).status, k < 2 ? 200 : 404) << k;
        poll_job(server.port(), later.back(), [](const json::value& j) {
            const auto st = state_of(j);
            return st == "succeeded" || st == "failed" || st == "cancelled";
        });
    }
    for (const auto& job : kept_jobs) EXPECT_FALSE(fs::exists(data / "jobs" / job));
    for (const auto& job : later) EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + job).status, 200);
}

// `study submit` reads its file once, so a pipe or /dev/stdin works: here a
// FIFO its writer fills once (a second open for reading, the old client's,
// found it empty and sent an empty body). A study the server refuses exits
// 3, as a job it refuses does (it exited 6).
TEST(Studies, StudySubmitReadsItsFileOnceAndExitsAsJobSubmitDoes)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--jobs", "1", "--max-study-points", "1"});
    const fs::path fifo = tmp.path() / "study.fifo";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string text = study_text("piped", {{"seed", json::array{1}}});
    std::thread writer([&] {
        std::ofstream(fifo) << text;  // once the client opens it
        for (int i = 0; i < 300; ++i) {  // a second reader, if one comes, finds it empty
            const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
            if (fd >= 0) {
                ::close(fd);
                break;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    });
    const auto piped = run_client({"study", "submit", fifo.string(), "--server", server.url()});
    writer.join();
    EXPECT_EQ(piped.exit_code, 0) << piped.err;

    write_file(tmp.path() / "two.json", study_text("two", {{"seed", json::array{1, 2}}}));
    const auto refused = run_client({"study", "submit", (tmp.path() / "two.json").string(), "--server", server.url()});
    EXPECT_EQ(refused.exit_code, 3) << refused.err;
    EXPECT_NE(refused.err.find("more than the limit of 1"), std::string::npos) << refused.err;
}

TEST(Studies, HostileStudiesAreRefusedWithTheFieldAndNothingIsCreated)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data",
        {"--max-study-points", "10", "--max-queued", "12", "--max-steps-per-job", "1e9", "--jobs", "1"}, 1.0);
    const auto refused = [&](const std::string& body, int status, const std::string& field, const std::string& text) {
        const auto r = http(server.port(), "POST", "/v1/studies", body);
        EXPECT_EQ(r.status, status) << body.substr(0, 200) << "\n" << r.body;
        if (!field.empty()) {
            EXPECT_EQ(json::value_to<std::string>(r.json().at("error").at("field")), field) << r.body;
        }
        EXPECT_NE(r.body.find(text), std::string::npos) << r.body;
    };
    // A grid over the limit, before any job is built.
    json::array many;
    for (int i = 1; i <= 11; ++i) many.emplace_back(i);
    refused(study_text("big", {{"seed", many}}), 400, "vary", "11 points (11), more than the limit of 10");
    // An unknown path, a value of the wrong type, one out of range.
    refused(study_text("typo", {{"specimen.grain_cont", json::array{10}}}), 400,
        "points[0] (specimen.grain_cont=10): specimen.grain_cont", "unknown");
    refused(study_text("type", {{"seed", json::array{1, "two"}}}), 400, "points[1] (seed=\"two\"): seed", "");
    refused(study_text("range", {{"triaxial.plate_speed_m_per_s", json::array{0.01, -1}}}), 400,
        "points[1] (triaxial.plate_speed_m_per_s=-1): triaxial.plate_speed_m_per_s", "");
    // A point the server would not run (its step limit).
    refused(study_text("slow", {{"triaxial.plate_speed_m_per_s", json::array{0.01, 1e-9}}}), 400,
        "points[1] (triaxial.plate_speed_m_per_s=1e-09): triaxial.plate_speed_m_per_s", "--max-steps-per-job");
    refused("[1, 2]", 400, "", "a study must be a JSON object");
    {  // a comment bounded as a job's
        json::object doc = json::parse(study_text("long", {{"seed", json::array{1}}})).as_object();
        doc["comment"] = std::string(10'001, 'x');
        refused(json::serialize(doc), 400, "comment", "at most 10000");
    }
    refused("{", 400, "", "invalid_json");
    // More jobs than the queue takes: 429, and none of them created.
    refused(study_text("q1", {{"seed", json::array{1, 2, 3, 4, 5, 6, 7, 8}}}), 201, "", "");
    refused(study_text("q2", {{"seed", json::array{1, 2, 3, 4, 5, 6}}}), 429, "", "do not fit in the queue");
    const json::value list = http(server.port(), "GET", "/v1/studies").json();
    EXPECT_EQ(list.at("studies").as_array().size(), 1u);
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs?limit=500").json().at("jobs").as_array().size(), 8u);

    // Without Content-Type; routes and ids.
    const auto r = raw_exchange(server.port(), "POST /v1/studies HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 2\r\n"
                                               "Connection: close\r\n\r\n{}");
    EXPECT_EQ(r.status, 415);
    EXPECT_EQ(http(server.port(), "GET", "/v1/studies/xyz").status, 400);
    EXPECT_EQ(http(server.port(), "GET", "/v1/studies/0123456789abcdef01234567").status, 404);
    EXPECT_EQ(http(server.port(), "GET", "/v1/studies/0123456789abcdef01234567/summary").status, 404);
    EXPECT_EQ(http(server.port(), "GET", "/v1/studies/0123456789abcdef01234567/other").status, 404);
    EXPECT_EQ(http(server.port(), "PUT", "/v1/studies").status, 405);
    EXPECT_EQ(http(server.port(), "GET", "/v1/studies?limit=0").status, 400);
    EXPECT_EQ(http(server.port(), "GET", "/v1/studies?colour=red").status, 400);

    // The client checks the document before sending it.
    write_file(tmp.path() / "bad.json", study_text("typo", {{"seed", json::array{1, -1}}}));
    const auto c = run_client({"study", "submit", (tmp.path() / "bad.json").string(), "--server", server.url()});
    EXPECT_EQ(c.exit_code, 3) << c.err;
    EXPECT_NE(c.err.find("points[1] (seed=-1): seed"), std::string::npos) << c.err;
}

// With the real runner: the same study run here (`wiredem study run`) and
// through the server gives the same summary, bit for bit (but for job ids).
TEST(StudiesRealRunner, TheSameStudyHereAndThroughTheServerGivesTheSameSummary)
{
    TempDir tmp;
    write_file(tmp.path() / "study.json", study_text("here-and-there", {{"seed", json::array{1, 2}}}));
    const auto here = run_client({"study", "run", (tmp.path() / "study.json").string(), "-o", (tmp.path() / "here").string(),
        "--jobs", "2", "--threads", "2"});
    ASSERT_EQ(here.exit_code, 0) << here.err;

    ServerProcess server(tmp.path() / "data",
        {"--runner", WIREDEM_CLIENT_BIN, "--jobs", "2", "--threads-per-job", "1", "--max-steps-per-job", "1e8"});
    const auto submitted = run_client({"study", "submit", (tmp.path() / "study.json").string(), "--wait", "--interval", "0.2",
        "--server", server.url()});
    ASSERT_EQ(submitted.exit_code, 0) << submitted.err << server.log();
    const std::string id = submitted.out.substr(0, submitted.out.find('\n'));
    const auto fetched = run_client({"study", "fetch", id, "-o", (tmp.path() / "there").string(), "--server", server.url()});
    ASSERT_EQ(fetched.exit_code, 0) << fetched.err;

    json::value a = json::parse(read_file(tmp.path() / "here/summary.json"));
    json::value b = json::parse(read_file(tmp.path() / "there/summary.json"));
    b.as_object().erase("id");
    for (json::value* s : {&a, &b})
        for (json::value& p : s->at("points").as_array()) p.as_object().erase("job_id");
    EXPECT_EQ(json::serialize(a), json::serialize(b));
    EXPECT_EQ(a.at("groups").as_array().at(0).at("succeeded").to_number<int>(), 2);
}

} // namespace wiredem::test
