// Responsiveness (a measurement, not a timed test): while a job keeps every
// core busy, 1000 status requests are answered; the percentiles are printed
// (and recorded as test properties) but not asserted, since they depend on
// the machine.
#include "harness.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

namespace wiredem::test {
namespace {
namespace json = boost::json;

TEST(Responsiveness, StatusLatencyWhileAJobBurnsEveryCore)
{
    TempDir tmp;
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    ServerProcess server(tmp.path() / "data", {"--jobs", "1", "--threads-per-job", std::to_string(cores)}, 0.3);
    const auto r = http(server.port(), "POST", "/v1/jobs", R"({"name": "slow-burn"})");
    ASSERT_EQ(r.status, 201);
    const std::string id(r.json().at("id").as_string());
    // The runner burns the cores from its start: wait until it has reported once.
    const auto started = poll_job(server.port(), id, [](const json::value& j) { return j.at("stage").is_string(); });
    ASSERT_EQ(state_of(started), "preparing");

    std::vector<double> ms;
    ms.reserve(1000);
    for (int i = 0; i < 1000; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        const auto reply = http(server.port(), "GET", "/v1/jobs/" + id);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        ASSERT_EQ(reply.status, 200);
    }
    const auto running = poll_job(server.port(), id, [](const json::value&) { return true; });
    EXPECT_TRUE(state_of(running) == "preparing" || state_of(running) == "running")
        << "the job was still burning the cores at the end";
    std::sort(ms.begin(), ms.end());
    const double p50 = ms[499];
    const double p99 = ms[989];
    const double max = ms.back();
    std::printf("[ latency  ] 1000 GET /v1/jobs/{id} (new connection each) while %u core(s) burn: "
                "p50 %.2f ms, p99 %.2f ms, max %.2f ms\n", cores, p50, p99, max);
    RecordProperty("p50_ms", std::to_string(p50));
    RecordProperty("p99_ms", std::to_string(p99));
    RecordProperty("max_ms", std::to_string(max));
    EXPECT_EQ(http(server.port(), "DELETE", "/v1/jobs/" + id).status, 200);
}

} // namespace
} // namespace wiredem::test
