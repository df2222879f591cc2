// The life of a job through the real server and the real client: submit,
// progress, success, summary, download (whole and resumed), cancel, list,
// failure, idempotent retries, queue bound.
#include "harness.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <set>
#include <thread>

namespace wiredem::test {
namespace {
namespace fs = std::filesystem;
namespace json = boost::json;

std::string submit(const ServerProcess& server, const TempDir& tmp, const std::string& name)
{
    const fs::path job = tmp.path() / (name + ".json");
    write_file(job, R"({"name": ")" + name + R"("})");
    const auto run = run_client({"submit", job.string(), "--server", server.url()});
    EXPECT_EQ(run.exit_code, 0) << run.err;
    std::string id = run.out;
    while (!id.empty() && (id.back() == '\n' || id.back() == '\r')) id.pop_back();
    EXPECT_EQ(id.size(), 24u) << run.out;
    return id;
}

bool is_running(const json::value& j) { return state_of(j) == "running"; }
bool is_final(const json::value& j)
{
    const auto s = state_of(j);
    return s == "succeeded" || s == "failed" || s == "cancelled";
}

TEST(Lifecycle, SubmitProgressSucceedSummaryAndDownloadThroughTheClient)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {}, 0.1);
    const std::string id = submit(server, tmp, "lifecycle");

    // Progress moves: several distinct values are seen while the job runs.
    std::set<double> seen;
    std::set<std::string> stages;
    for (int i = 0; i < 400; ++i) {
        const auto st = run_client({"status", id, "--json", "--server", server.url()});
        ASSERT_EQ(st.exit_code, 0) << st.err;
        const json::value job = json::parse(st.out);
        if (job.at("progress").is_number()) seen.insert(job.at("progress").to_number<double>());
        if (job.at("stage").is_string()) stages.insert(std::string(job.at("stage").get_string()));
        if (is_final(job)) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    EXPECT_GE(seen.size(), 3u) << "progress should move";
    EXPECT_TRUE(stages.count("testing")) << "stages reported by the runner reach the API";

    const auto wait = run_client({"wait", id, "--interval", "0.05", "--server", server.url()});
    EXPECT_EQ(wait.exit_code, 0) << wait.err;
    EXPECT_NE(wait.out.find("succeeded"), std::string::npos) << wait.out;

    const auto summary = run_client({"summary", id, "--server", server.url()});
    ASSERT_EQ(summary.exit_code, 0) << summary.err;
    EXPECT_NE(summary.out.find("Mohr-Coulomb"), std::string::npos) << summary.out;
    EXPECT_NE(summary.out.find("41.25 deg"), std::string::npos) << summary.out;  // φ of the fake summary
    EXPECT_NE(summary.out.find("152.0"), std::string::npos) << summary.out;      // peak q at 40 kPa [kPa]

    const fs::path out = tmp.path() / "fetched";
    const auto fetch = run_client({"fetch", id, "-o", out.string(), "--server", server.url()});
    ASSERT_EQ(fetch.exit_code, 0) << fetch.err;
    const fs::path stored = tmp.path() / "data" / "jobs" / id;
    EXPECT_EQ(read_file(out / "result.h5"), read_file(stored / "result.h5"));
    EXPECT_EQ(read_file(out / "result.h5").substr(0, 8), "1\n2\n3\n4\n");
    const json::value fetched_summary = json::parse(read_file(out / "summary.json"));
    EXPECT_DOUBLE_EQ(fetched_summary.at("mohr_coulomb").at("friction_angle_deg").to_number<double>(), 41.25);
    EXPECT_FALSE(fs::exists(out / "result.h5.part"));
}

TEST(Lifecycle, FetchResumesAPartialDownloadWithARange)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {}, 0.02);
    const std::string id = submit(server, tmp, "resume");
    ASSERT_EQ(state_of(poll_job(server.port(), id, is_final)), "succeeded");
    const std::string whole = read_file(tmp.path() / "data" / "jobs" / id / "result.h5");
    ASSERT_GT(whole.size(), 100000u);

    // An interrupted download left the first 100 000 bytes behind, with the
    // ETag of the result they came from.
    const std::string etag = http(server.port(), "HEAD", "/v1/jobs/" + id + "/result.h5").headers.at("etag");
    const fs::path out = tmp.path() / "partial";
    fs::create_directories(out);
    write_file(out / "result.h5.part", whole.substr(0, 100000));
    write_file(out / "result.h5.part.etag", etag + "\n");
    const auto fetch = run_client({"fetch", id, "-o", out.string(), "--json", "--server", server.url()});
    ASSERT_EQ(fetch.exit_code, 0) << fetch.err;
    const json::value report = json::parse(fetch.out);
    EXPECT_EQ(report.at("resumed_from").to_number<std::uint64_t>(), 100000u);
    EXPECT_EQ(read_file(out / "result.h5"), whole);
    EXPECT_EQ(read_file(out / "result.h5.etag"), etag + "\n");

    // A partial of another result (another job's, or one whose ETag was not
    // kept) is not spliced with this one's bytes: the download starts over.
    for (const std::string& other_tag : {std::string("\"another-job\"\n"), std::string()}) {
        const fs::path spliced = tmp.path() / ("spliced" + std::to_string(other_tag.size()));
        fs::create_directories(spliced);
        write_file(spliced / "result.h5.part", std::string(100000, 'x'));
        if (!other_tag.empty()) write_file(spliced / "result.h5.part.etag", other_tag);
        const auto again = run_client({"fetch", id, "-o", spliced.string(), "--json", "--server", server.url()});
        ASSERT_EQ(again.exit_code, 0) << again.err;
        EXPECT_EQ(json::parse(again.out).at("resumed_from").to_number<std::uint64_t>(), 0u);
        EXPECT_EQ(read_file(spliced / "result.h5"), whole) << "with a partial tagged '" << other_tag << "'";
    }
    // A result.h5 of the right size but not of this result is replaced.
    write_file(out / "result.h5", std::string(whole.size(), 'y'));
    write_file(out / "result.h5.etag", "\"another-job\"\n");
    ASSERT_EQ(run_client({"fetch", id, "-o", out.string(), "--server", server.url()}).exit_code, 0);
    EXPECT_EQ(read_file(out / "result.h5"), whole);

    // The server side of it: 206 with Content-Range, 416 past the end, HEAD with the size.
    const auto part = http(server.port(), "GET", "/v1/jobs/" + id + "/result.h5", {}, {{"Range", "bytes=10-19"}});
    EXPECT_EQ(part.status, 206);
    EXPECT_EQ(part.headers.at("content-range"), "bytes 10-19/" + std::to_string(whole.size()));
    EXPECT_EQ(part.body, whole.substr(10, 10));
    const auto suffix = http(server.port(), "GET", "/v1/jobs/" + id + "/result.h5", {}, {{"Range", "bytes=-5"}});
    EXPECT_EQ(suffix.status, 206);
    EXPECT_EQ(suffix.body, whole.substr(whole.size() - 5));
    const auto beyond = http(server.port(), "GET", "/v1/jobs/" + id + "/result.h5", {},
        {{"Range", "bytes=" + std::to_string(whole.size()) + "-"}});
    EXPECT_EQ(beyond.status, 416);
    EXPECT_EQ(beyond.headers.at("content-range"), "bytes */" + std::to_string(whole.size()));
    const auto head = http(server.port(), "HEAD", "/v1/jobs/" + id + "/result.h5");
    EXPECT_EQ(head.status, 200);
    EXPECT_EQ(head.headers.at("content-length"), std::to_string(whole.size()));
    EXPECT_TRUE(head.body.empty());
    const auto stale = http(server.port(), "GET", "/v1/jobs/" + id + "/result.h5", {},
        {{"Range", "bytes=10-19"}, {"If-Range", "\"not-the-etag\""}});
    EXPECT_EQ(stale.status, 200) << "If-Range that does not match sends the whole file";
    EXPECT_EQ(stale.body.size(), whole.size());
}

TEST(Lifecycle, CancelStopsTheRunningJobAndDropsTheQueuedOne)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--jobs", "1"}, 0.2);
    const std::string running = submit(server, tmp, "slow-running");
    const std::string queued = submit(server, tmp, "slow-queued");
    ASSERT_EQ(state_of(poll_job(server.port(), running, is_running)), "running");
    EXPECT_EQ(state_of(poll_job(server.port(), queued, [](const json::value&) { return true; })), "queued");

    const auto t0 = std::chrono::steady_clock::now();
    const auto cancel = run_client({"cancel", running, "--server", server.url()});
    EXPECT_EQ(cancel.exit_code, 0) << cancel.err;
    EXPECT_NE(cancel.out.find("cancelled"), std::string::npos);
    const auto cancel_queued = run_client({"cancel", queued, "--json", "--server", server.url()});
    EXPECT_EQ(cancel_queued.exit_code, 0) << cancel_queued.err;
    EXPECT_EQ(state_of(json::parse(cancel_queued.out)), "cancelled");

    // The runner is gone within a second: the worker is free and logs it.
    bool stopped = false;
    while (!stopped && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(3)) {
        stopped = server.log().find("job " + running + ": cancelled, runner exited with status 143") != std::string::npos;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    EXPECT_TRUE(stopped) << server.log();
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(1500));
    EXPECT_FALSE(fs::exists(tmp.path() / "data" / "jobs" / running / "result.h5"));

    const auto wait = run_client({"wait", running, "--server", server.url()});
    EXPECT_EQ(wait.exit_code, 8) << "documented exit code of a cancelled job";
    const auto again = http(server.port(), "DELETE", "/v1/jobs/" + running);
    EXPECT_EQ(again.status, 200) << "cancelling twice is harmless";
    const auto summary = run_client({"summary", running, "--server", server.url()});
    EXPECT_EQ(summary.exit_code, 6) << summary.err;  // 409: no results
}

TEST(Lifecycle, ListPagesNewestFirstAndFiltersByState)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {"--jobs", "1"}, 0.02);
    std::vector<std::string> ids;
    for (int i = 0; i < 5; ++i) ids.push_back(submit(server, tmp, "list" + std::to_string(i)));
    for (const auto& id : ids) ASSERT_EQ(state_of(poll_job(server.port(), id, is_final)), "succeeded");
    const std::string failed = submit(server, tmp, "fail-on-purpose");
    ASSERT_EQ(state_of(poll_job(server.port(), failed, is_final)), "failed");

    const auto page1 = http(server.port(), "GET", "/v1/jobs?limit=2");
    ASSERT_EQ(page1.status, 200);
    const json::value doc1 = page1.json();
    const auto& jobs1 = doc1.at("jobs").as_array();
    ASSERT_EQ(jobs1.size(), 2u);
    EXPECT_EQ(jobs1[0].at("id").as_string(), failed);  // newest first
    EXPECT_EQ(jobs1[1].at("id").as_string(), ids[4]);
    const std::string cursor(doc1.at("next_cursor").as_string());
    const auto page2 = http(server.port(), "GET", "/v1/jobs?limit=2&cursor=" + cursor);
    EXPECT_EQ(page2.json().at("jobs").as_array()[0].at("id").as_string(), ids[3]);

    const auto ok = http(server.port(), "GET", "/v1/jobs?state=succeeded&limit=500");
    EXPECT_EQ(ok.json().at("jobs").as_array().size(), 5u);
    const auto list = run_client({"list", "--state", "failed", "--server", server.url()});
    ASSERT_EQ(list.exit_code, 0) << list.err;
    EXPECT_NE(list.out.find(failed), std::string::npos);
    EXPECT_EQ(list.out.find(ids[0]), std::string::npos);
    const auto all = run_client({"list", "--all", "--limit", "2", "--json", "--server", server.url()});
    ASSERT_EQ(all.exit_code, 0) << all.err;
    EXPECT_EQ(json::parse(all.out).at("jobs").as_array().size(), 6u);
}

TEST(Lifecycle, FailedRunnerReportsItsLastStderrLine)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {}, 0.02);
    const std::string id = submit(server, tmp, "fail-please");
    const auto wait = run_client({"wait", id, "--server", server.url()});
    EXPECT_EQ(wait.exit_code, 1);
    EXPECT_NE(wait.err.find("the specimen collapsed while pouring"), std::string::npos) << wait.err;
    const auto job = poll_job(server.port(), id, is_final);
    EXPECT_EQ(job.at("error").as_string(),
        "fake runner: the specimen collapsed while pouring (job name asks for a failure)");
    EXPECT_EQ(http(server.port(), "GET", "/v1/jobs/" + id + "/result.h5").status, 409);
}

TEST(Lifecycle, SubmitWithWaitAndIdempotencyKeyReplaysTheFirstJob)
{
    TempDir tmp;
    ServerProcess server(tmp.path() / "data", {}, 0.02);
    const fs::path job = tmp.path() / "job.json";
    write_file(job, R"({"name": "waited"})");
    const auto run = run_client({"submit", job.string(), "--wait", "--interval", "0.05", "--server", server.url()});
    EXPECT_EQ(run.exit_code, 0) << run.err;
    EXPECT_NE(run.out.find("succeeded"), std::string::npos);

    const std::string body = R"({"name": "idem"})";
    const auto first = http(server.port(), "POST", "/v1/jobs", body, {{"Idempotency-Key", "key-1"}});
    const auto second = http(server.port(), "POST", "/v1/jobs", body, {{"Idempotency-Key", "key-1"}});
    ASSERT_EQ(first.status, 201);
    EXPECT_EQ(second.status, 201);
    EXPECT_EQ(second.headers.at("idempotent-replayed"), "true");
    EXPECT_EQ(first.json().at("id"), second.json().at("id"));
    const auto other = http(server.port(), "POST", "/v1/jobs", R"({"name": "other"})", {{"Idempotency-Key", "key-1"}});
    EXPECT_EQ(other.status, 409);
    EXPECT_EQ(other.error_code(), "idempotency_conflict");
}

TEST(Lifecycle, FullQueueAnswers429WithRetryAfter)
{
    TempDir tmp;
    // Slow fake steps (1 s). The first job is running before the queue is
    // filled: had the worker taken a queued job between the 429 and the
    // client's submit, the client would have found room (seen once in 40 runs
    // on a loaded machine).
    ServerProcess server(tmp.path() / "data", {"--jobs", "1", "--max-queued", "2", "--retry-after", "7"}, 1.0);
    const std::string running = submit(server, tmp, "slow-running");
    ASSERT_EQ(state_of(poll_job(server.port(), running, is_running)), "running");
    const std::string body = R"({"name": "slow-fill"})";
    int accepted = 0;
    RawReply last;
    for (int i = 0; i < 6 && last.status != 429; ++i) {
        last = http(server.port(), "POST", "/v1/jobs", body);
        if (last.status == 201) ++accepted;
    }
    EXPECT_EQ(last.status, 429);
    EXPECT_EQ(last.headers.at("retry-after"), "7");
    EXPECT_EQ(last.error_code(), "queue_full");
    EXPECT_EQ(accepted, 2); // the queue's two, the worker busy with the first
    const fs::path job = tmp.path() / "job.json";
    write_file(job, body);
    const auto run = run_client({"submit", job.string(), "--server", server.url()});
    EXPECT_EQ(run.exit_code, 6);
    EXPECT_NE(run.err.find("retry after 7 s"), std::string::npos) << run.err;
}

} // namespace
} // namespace wiredem::test
