// The result data routes (server/handlers/results.hpp) against a result.h5
// written here with known values in wiredem's layout (docs/results.md): the
// fake runner hands it over as the job's result (WIREDEM_FAKE_RESULT_DIR), so
// every figure the routes return can be compared with what was written.
#include "harness.hpp"

#include "files.hpp"
#include "io/hdf5.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <future>
#include <numbers>
#include <set>
#include <thread>

namespace wiredem::test {
namespace {
namespace fs = std::filesystem;
namespace json = boost::json;
namespace io = engine::io;

constexpr std::size_t rows = 101;
constexpr std::size_t grains = 7;
constexpr std::size_t segments = 64;
constexpr std::size_t period_segments = 8;  ///< the wire strain's period, in segments
/// The wire strain's alternating part, 0.3 of its wave: it bends R̂ into a local
/// maximum at half the period whose prominence (0.04) is below the noise band
/// 1.96/√(64 − 4) = 0.25, so the first maximum (4 segments) and the first
/// prominent one (8) differ.
constexpr double alternating_fraction = 0.3;
constexpr std::size_t first_maximum_segments = period_segments / 2;
constexpr double segment_length_m = 2e-3;   ///< the submitted spec's l_w

/// Column `name` of the test at `sigma3`, row i: distinct per test, column and row.
double value(double sigma3, int column, std::size_t i) { return sigma3 + 1000.0 * column + 0.25 * static_cast<double>(i); }

const std::vector<std::string> column_names{"time_s", "axial_strain", "deviatoric_stress_pa"};

/// Three tests named so that text order (100000, 20000, 5000) is not pressure order.
void write_result(const fs::path& dir)
{
    fs::create_directories(dir);
    io::File file = io::File::create(dir / "result.h5");
    io::Group root = file.root();
    root.write_string_attribute("format", "wiredem-result-1");
    root.write_string_dataset("job_spec", R"({"name": "results", "specimen": {"wire": {"segment_length_m": 0.002}}})");
    io::Group sp = root.create_group("specimen");
    sp.write_int_attribute("grains", grains);
    std::vector<double> pos(grains * 3), radius(grains);
    for (std::size_t i = 0; i < pos.size(); ++i) pos[i] = 0.001 * static_cast<double>(i) + 1e-9;
    for (std::size_t i = 0; i < grains; ++i) radius[i] = 1e-3 + 1e-5 * static_cast<double>(i);
    sp.write_dataset("grain_position_m", std::span<const double>(pos), 3).write_string_attribute("units", "m");
    sp.write_dataset("grain_radius_m", std::span<const double>(radius)).write_string_attribute("units", "m");
    for (double sigma3 : {100000.0, 20000.0, 5000.0}) {
        io::Group t = root.create_group("tests/sigma3_" + std::to_string(static_cast<long>(sigma3)));
        t.write_double_attribute("confining_pressure_pa", sigma3);
        t.write_double_attribute("peak_deviatoric_stress_pa", 3 * sigma3);
        for (int c = 0; c < static_cast<int>(column_names.size()); ++c) {
            std::vector<double> v(rows);
            for (std::size_t i = 0; i < rows; ++i) v[i] = value(sigma3, c, i);
            t.write_dataset(column_names[static_cast<std::size_t>(c)], std::span<const double>(v)).write_string_attribute("units", "1");
        }
        std::vector<std::int32_t> phase(rows, 2);
        t.write_dataset("phase", std::span<const std::int32_t>(phase));
        for (int k = 0; k < 2; ++k) {
            io::Group s = t.create_group("snapshots/snapshot_" + std::to_string(k));
            s.write_double_attribute("requested_axial_strain", 0.05 * k);
            s.write_double_attribute("axial_strain", 0.05 * k + 1e-4);
            s.write_dataset("grain_position_m", std::span<const double>(pos), 3);
            std::vector<double> strain(segments);
            for (std::size_t j = 0; j < segments; ++j)
                strain[j] = 1e-3 * (std::sin(2 * std::numbers::pi * static_cast<double>(j) / period_segments)
                                       + (j % 2 == 0 ? alternating_fraction : -alternating_fraction));
            s.write_dataset("wire_segment_strain", std::span<const double>(strain));
            const std::vector<std::uint32_t> tri{0, 1, 2, 2, 3, 4};
            s.write_dataset("membrane_triangles", std::span<const std::uint32_t>(tri), 3);
        }
    }
    write_file(dir / "result.xdmf", "<?xml version=\"1.0\"?><Xdmf/>\n");
}

class ResultData : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        tmp_ = new TempDir;
        write_result(tmp_->path() / "made");
        ::setenv("WIREDEM_FAKE_RESULT_DIR", (tmp_->path() / "made").c_str(), 1);
        server_ = new ServerProcess(tmp_->path() / "data", {}, 0.02);
        ::unsetenv("WIREDEM_FAKE_RESULT_DIR");
        const auto res = http(server_->port(), "POST", "/v1/jobs",
            R"({"name": "results", "specimen": {"wire": {"segment_length_m": )" + std::to_string(segment_length_m) + "}}}");
        ASSERT_EQ(res.status, 201) << res.body;
        id_ = std::string(res.json().at("id").get_string());
        const auto job = poll_job(server_->port(), id_, [](const json::value& j) { return state_of(j) == "succeeded"; });
        ASSERT_EQ(state_of(job), "succeeded") << server_->log();
    }
    static void TearDownTestSuite()
    {
        delete server_;
        delete tmp_;
    }
    static RawReply get(const std::string& path) { return http(server_->port(), "GET", "/v1/jobs/" + id_ + path); }

    static inline TempDir* tmp_ = nullptr;
    static inline ServerProcess* server_ = nullptr;
    static inline std::string id_;
};

TEST_F(ResultData, TestsAreListedByAscendingPressureWithColumnsAndSnapshots)
{
    const auto res = get("/tests");
    ASSERT_EQ(res.status, 200) << res.body;
    const json::value body = res.json();
    const auto& tests = body.at("tests").as_array();
    ASSERT_EQ(tests.size(), 3u);
    const char* expected[] = {"sigma3_5000", "sigma3_20000", "sigma3_100000"};
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(tests[i].at("name").get_string(), expected[i]);
        EXPECT_EQ(tests[i].at("rows").to_number<std::size_t>(), rows);
        EXPECT_EQ(tests[i].at("columns").as_array().size(), column_names.size() + 1);  // + phase
        EXPECT_EQ(tests[i].at("snapshots").as_array().size(), 2u);
    }
    EXPECT_DOUBLE_EQ(tests[1].at("attributes").at("peak_deviatoric_stress_pa").to_number<double>(), 60000.0);
    EXPECT_DOUBLE_EQ(tests[2].at("snapshots").at(1).at("axial_strain").to_number<double>(), 0.05 + 1e-4);
}

TEST_F(ResultData, SeriesHoldTheStoredValuesAndThinEvenlyKeepingBothEnds)
{
    const auto all = get("/tests/sigma3_20000/series");
    ASSERT_EQ(all.status, 200) << all.body;
    const json::value body = all.json();
    EXPECT_EQ(body.at("rows").to_number<std::size_t>(), rows);
    const auto& q = body.at("columns").at("deviatoric_stress_pa").as_array();
    ASSERT_EQ(q.size(), rows);
    for (std::size_t i = 0; i < rows; ++i) EXPECT_EQ(q[i].to_number<double>(), value(20000, 2, i)) << i;

    const auto thin = get("/tests/sigma3_20000/series?max_points=5&columns=axial_strain,time_s");
    ASSERT_EQ(thin.status, 200) << thin.body;
    const json::value t = thin.json();
    EXPECT_EQ(t.at("returned_rows").to_number<std::size_t>(), 5u);
    EXPECT_EQ(t.at("columns").as_object().size(), 2u);
    const std::size_t want[] = {0, 25, 50, 75, 100};
    for (std::size_t k = 0; k < 5; ++k) {
        EXPECT_EQ(t.at("row_index").at(k).to_number<std::size_t>(), want[k]);
        EXPECT_EQ(t.at("columns").at("axial_strain").at(k).to_number<double>(), value(20000, 1, want[k]));
    }
    // More points than rows: every row.
    EXPECT_EQ(get("/tests/sigma3_20000/series?max_points=1000").json().at("returned_rows").to_number<std::size_t>(), rows);
}

TEST_F(ResultData, BadSeriesParametersAreClear400s)
{
    for (const char* query : {"?max_points=1", "?max_points=0", "?max_points=abc", "?max_points=", "?max_points=1000001",
             "?max_points=5&max_points=6", "?columns=nope", "?columns=time_s,", "?limit=3"}) {
        const auto res = get(std::string("/tests/sigma3_20000/series") + query);
        EXPECT_EQ(res.status, 400) << query;
        EXPECT_EQ(res.error_code(), "bad_parameter") << query;
        EXPECT_FALSE(res.json().at("error").at("field").is_null()) << query;
    }
    EXPECT_EQ(get("/tests?max_points=5").status, 400) << "only the series route takes parameters";
}

TEST_F(ResultData, ArraysAreLittleEndianFloat32AndInt32WithTheirShape)
{
    const auto pos = get("/tests/sigma3_5000/snapshots/1/grain_position_m");
    ASSERT_EQ(pos.status, 200) << pos.body;
    EXPECT_EQ(pos.headers.at("x-wiredem-shape"), std::to_string(grains) + ",3");
    EXPECT_EQ(pos.headers.at("x-wiredem-dtype"), "float32");
    ASSERT_EQ(pos.body.size(), grains * 3 * sizeof(float));
    for (std::size_t i = 0; i < grains * 3; ++i) {
        float f;
        std::memcpy(&f, pos.body.data() + i * sizeof f, sizeof f);
        EXPECT_EQ(f, static_cast<float>(0.001 * static_cast<double>(i) + 1e-9)) << i;
    }
    const auto tri = get("/tests/sigma3_5000/snapshots/0/membrane_triangles");
    ASSERT_EQ(tri.status, 200);
    EXPECT_EQ(tri.headers.at("x-wiredem-shape"), "2,3");
    EXPECT_EQ(tri.headers.at("x-wiredem-dtype"), "int32");
    std::int32_t idx[6];
    ASSERT_EQ(tri.body.size(), sizeof idx);
    std::memcpy(idx, tri.body.data(), sizeof idx);
    EXPECT_EQ(idx[3], 2);
    EXPECT_EQ(idx[5], 4);

    const auto specimen = get("/specimen");
    ASSERT_EQ(specimen.status, 200);
    EXPECT_EQ(specimen.json().at("attributes").at("grains").to_number<std::size_t>(), grains);
    EXPECT_EQ(specimen.json().at("arrays").as_array().size(), 2u);
    EXPECT_EQ(get("/specimen/grain_radius_m").body.size(), grains * sizeof(float));
}

TEST_F(ResultData, WireAutocorrelationFindsTheStrainsPeriodWithTheSpecsSegmentLength)
{
    const auto res = get("/tests/sigma3_100000/snapshots/0/wire_autocorrelation");
    ASSERT_EQ(res.status, 200) << res.body;
    const json::value b = res.json();
    EXPECT_TRUE(b.at("error").is_null()) << res.body;
    EXPECT_EQ(b.at("segments").to_number<std::size_t>(), segments);
    EXPECT_DOUBLE_EQ(b.at("first_maximum_lag_m").to_number<double>(), first_maximum_segments * segment_length_m);
    EXPECT_DOUBLE_EQ(b.at("prominent_maximum_lag_m").to_number<double>(), period_segments * segment_length_m);
    EXPECT_DOUBLE_EQ(b.at("coefficients").at(0).to_number<double>(), 1.0);
}

TEST_F(ResultData, WhatTheFileDoesNotHoldIs404)
{
    for (const char* path : {"/tests/sigma3_7", "/tests/sigma3_5000/snapshots/2", "/tests/sigma3_5000/snapshots/01x",
             "/tests/sigma3_5000/snapshots/0/nope", "/tests/sigma3_5000/snapshots/0/..", "/specimen/nope",
             "/tests/sigma3_5000/other", "/tests/sigma3_5000/snapshots/0/grain_position_m/x"})
        EXPECT_EQ(get(path).status, 404) << path;
    EXPECT_EQ(http(server_->port(), "GET", "/v1/jobs/xyz/tests").error_code(), "bad_id");
    EXPECT_EQ(http(server_->port(), "GET", "/v1/jobs/0123456789abcdef01234567/tests").status, 404);
    EXPECT_EQ(http(server_->port(), "DELETE", "/v1/jobs/" + id_ + "/tests").status, 405);
}

TEST_F(ResultData, ResultXdmfIsServedAndHeadGivesItsLength)
{
    const auto x = get("/result.xdmf");
    ASSERT_EQ(x.status, 200) << x.body;
    EXPECT_EQ(x.body, "<?xml version=\"1.0\"?><Xdmf/>\n");
    EXPECT_EQ(x.headers.at("content-type"), "application/xml");
    const auto head = http(server_->port(), "HEAD", "/v1/jobs/" + id_ + "/result.xdmf");
    EXPECT_EQ(head.headers.at("content-length"), std::to_string(x.body.size()));
}

TEST_F(ResultData, TheReportNeedsTheWebPageToDrawWith)
{
    // This server has the default web folder only in a build that made the page.
    const auto res = get("/report.html");
    if (res.status == 200) {
        EXPECT_EQ(res.headers.at("content-disposition"), "attachment; filename=\"report.html\"");
        EXPECT_NE(res.body.find("id=\"report-data\""), std::string::npos);
        EXPECT_NE(res.body.find("\"sigma3_100000\""), std::string::npos) << "the tests are in it";
    } else {
        EXPECT_EQ(res.status, 404) << res.body;
    }
    TempDir tmp;
    ServerProcess bare(tmp.path() / "data", {"--web-dir", "none"});
    EXPECT_EQ(http(bare.port(), "GET", "/v1/jobs/" + id_ + "/report.html").status, 404) << "no such job there, and no page";
}

TEST_F(ResultData, AJobThatHasNotSucceededHasNoResultData)
{
    const auto res = http(server_->port(), "POST", "/v1/jobs", R"({"name": "fail here"})");
    ASSERT_EQ(res.status, 201);
    const std::string id(res.json().at("id").get_string());
    poll_job(server_->port(), id, [](const json::value& j) { return state_of(j) == "failed"; });
    EXPECT_EQ(http(server_->port(), "GET", "/v1/jobs/" + id + "/tests").error_code(), "not_succeeded");
}

TEST_F(ResultData, TheOpenApiDocumentDescribesTheRoutes)
{
    const json::value doc = http(server_->port(), "GET", "/v1/openapi.json").json();
    const auto& paths = doc.at("paths").as_object();
    for (const char* p : {"/v1/jobs/{id}/tests", "/v1/jobs/{id}/tests/{test}/series", "/v1/jobs/{id}/specimen",
             "/v1/jobs/{id}/specimen/{array}", "/v1/jobs/{id}/tests/{test}/snapshots/{k}",
             "/v1/jobs/{id}/tests/{test}/snapshots/{k}/{array}", "/v1/jobs/{id}/tests/{test}/snapshots/{k}/wire_autocorrelation",
             "/v1/jobs/{id}/result.xdmf", "/v1/jobs/{id}/report.html"})
        EXPECT_TRUE(paths.contains(p)) << p;
    // Every $ref the merged document holds points at something it defines.
    std::vector<const json::value*> todo{&doc};
    while (!todo.empty()) {
        const json::value* v = todo.back();
        todo.pop_back();
        if (const auto* o = v->if_object()) {
            if (auto it = o->find("$ref"); it != o->end()) {
                const std::string ref(it->value().get_string());
                ASSERT_EQ(ref.rfind("#/", 0), 0u) << ref;
                EXPECT_NO_THROW((void)doc.at_pointer(ref.substr(1))) << ref;
            }
            for (const auto& [k, child] : *o) todo.push_back(&child);
        } else if (const auto* a = v->if_array()) {
            for (const auto& child : *a) todo.push_back(&child);
        }
    }
}

} // namespace
} // namespace wiredem::test

namespace wiredem::test {
namespace {

TEST_F(ResultData, TheJobSpecSchemaIsServedAndInTheOpenApiDocumentInItsDialect)
{
    const auto res = http(server_->port(), "GET", "/v1/job-spec/schema");
    ASSERT_EQ(res.status, 200);
    EXPECT_EQ(res.headers.at("content-type"), "application/schema+json");
    const json::value schema = res.json();
    const json::value& radius = schema.at_pointer("/properties/specimen/properties/membrane_radius_m");
    EXPECT_EQ(radius.at("exclusiveMinimum").to_number<double>(), 0.0);
    EXPECT_EQ(radius.at("maximum").to_number<double>(), 1.0);

    // OpenAPI 3.0: exclusive bounds are flags, nullable instead of a type list, no const.
    const json::value doc = http(server_->port(), "GET", "/v1/openapi.json").json();
    const json::value& spec = doc.at_pointer("/components/schemas/JobSpec");
    const json::value& r30 = spec.at_pointer("/properties/specimen/properties/membrane_radius_m");
    EXPECT_EQ(r30.at("minimum").to_number<double>(), 0.0);
    EXPECT_EQ(r30.at("exclusiveMinimum"), true);
    const json::value& length = spec.at_pointer("/properties/specimen/properties/wire/properties/length_m");
    EXPECT_EQ(length.at("type"), "number");
    EXPECT_EQ(length.at("nullable"), true);
    EXPECT_EQ(json::serialize(spec).find("\"const\""), std::string::npos);
    EXPECT_EQ(json::serialize(spec).find("$schema"), std::string::npos);
}

} // namespace
} // namespace wiredem::test

namespace wiredem::test {
namespace {

/// Column `name` of a series reply as doubles.
std::vector<double> column_of(const json::value& series, const char* name)
{
    std::vector<double> out;
    for (const auto& x : series.at("columns").at(name).as_array()) out.push_back(x.to_number<double>());
    return out;
}

/// Every partial series is the beginning of the finished one, bit for bit,
/// in each of `columns`.
void expect_partials_begin_the_final_series(
    const json::value& final_series, const std::vector<json::value>& partial, std::initializer_list<const char*> columns)
{
    EXPECT_FALSE(final_series.at("partial").as_bool());
    for (const char* column : columns) {
        const std::vector<double> all = column_of(final_series, column);
        for (const json::value& p : partial) {
            const std::vector<double> head = column_of(p, column);
            ASSERT_LT(head.size(), all.size());
            EXPECT_TRUE(std::equal(head.begin(), head.end(), all.begin())) << column << ": a partial series is not the start of the final one";
        }
    }
}

// With the real runner, checkpoints every 50 ms: while a job runs, its first
// test's series grows from the checkpoints (marked partial, with how far it
// reached), and every partial series is the beginning of the finished one,
// bit for bit: the route reads what the runner recorded, nothing else.
TEST(LiveSeriesRealRunner, ARunningTestsSeriesGrowsAndIsTheBeginningOfTheFinishedOne)
{
    namespace fs = std::filesystem;
    TempDir tmp;
    json::object spec = json::parse(read_file(fs::path(WIREDEM_SOURCE_DIR) / "examples/tiny.json")).as_object();
    spec["triaxial"].as_object()["plate_speed_m_per_s"] = 0.02;  // the loading twice as long as tiny's
    ServerProcess server(tmp.path() / "data", {"--runner", WIREDEM_CLIENT_BIN, "--jobs", "1", "--threads-per-job", "1",
        "--checkpoint-seconds", "0.05", "--max-steps-per-job", "1e8"});
    const auto r = http(server.port(), "POST", "/v1/jobs", json::serialize(spec));
    ASSERT_EQ(r.status, 201) << r.body;
    const std::string id(r.json().at("id").as_string());
    const std::string series = "/v1/jobs/" + id + "/tests/sigma3_10000/series?columns=time_s,deviatoric_stress_pa,phase";

    std::vector<json::value> partial;  // each reply that had grown
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    for (;;) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        const json::value job = http(server.port(), "GET", "/v1/jobs/" + id).json();
        if (state_of(job) == "succeeded") break;
        ASSERT_TRUE(state_of(job) == "queued" || state_of(job) == "preparing" || state_of(job) == "running") << server.log();
        ASSERT_LT(std::chrono::steady_clock::now(), deadline) << server.log();
        const auto reply = http(server.port(), "GET", series);
        if (reply.status == 409) continue;  // queued, or succeeded meanwhile
        ASSERT_EQ(reply.status, 200) << reply.body;
        const json::value s = reply.json();
        if (!s.at("partial").as_bool()) continue;  // finished already
        const std::size_t rows = s.at("rows").to_number<std::size_t>();
        if (rows == 0) {
            EXPECT_EQ(s.at("state"), "waiting");
            EXPECT_TRUE(s.at("reached").is_null());
            continue;
        }
        EXPECT_EQ(s.at("state"), "running");
        EXPECT_EQ(s.at("reached").at("rows").to_number<std::size_t>(), rows);
        EXPECT_EQ(s.at("reached").at("time_s").to_number<double>(), column_of(s, "time_s").back());
        if (partial.empty() || rows > partial.back().at("rows").to_number<std::size_t>()) partial.push_back(s);

        const auto tests_reply = http(server.port(), "GET", "/v1/jobs/" + id + "/tests");
        ASSERT_EQ(tests_reply.status, 200) << tests_reply.body << server.log();
        const json::value tests = tests_reply.json();
        EXPECT_TRUE(tests.at("partial").as_bool());
        ASSERT_EQ(tests.at("tests").as_array().size(), 2u);
        EXPECT_EQ(tests.at("tests").at(0).at("name"), "sigma3_10000");
    }
    ASSERT_GE(partial.size(), 2u) << "the series should have grown at least once while the test ran";

    const auto done = http(server.port(), "GET", series);
    ASSERT_EQ(done.status, 200);
    const json::value final_series = done.json();
    expect_partials_begin_the_final_series(final_series, partial, {"time_s", "deviatoric_stress_pa", "phase"});
    // A running test has no volumetric strain yet (derived when it ends): not among its columns.
    EXPECT_FALSE(partial.front().at("units").as_object().contains("volumetric_strain"));
}

// The free-standing test likewise: while it runs, its route and series read
// its last checkpoint (every 50 ms here), marked partial and running, with
// how far it reached; every partial series is the beginning of the finished
// one, bit for bit, and the finished reply is not partial.
TEST(LiveSeriesRealRunner, ARunningFreeStandingTestsSeriesGrowsAndIsTheBeginningOfTheFinishedOne)
{
    namespace fs = std::filesystem;
    TempDir tmp;
    json::object spec = json::parse(read_file(fs::path(WIREDEM_SOURCE_DIR) / "examples/tiny.json")).as_object();
    spec["triaxial"].as_object()["confining_pressures_pa"] = json::array{10000};
    spec["triaxial"].as_object()["target_axial_strain"] = 0.01;
    spec["triaxial"].as_object()["snapshot_strains"] = json::array{0.0, 0.01};
    // Removal and loading long enough (0.4 s of simulated time, about 70 000
    // steps, 0.7 s of wall time on one idle core: some 14 checkpoints) that
    // the 20 ms polls see the series grow even on a loaded machine. With 0.01 s
    // of removal and a plate at 0.05 m/s the test took 0.1 s of wall time, two
    // checkpoints, and a loaded CI run saw only one of them.
    spec["free_standing"] = json::object{{"enabled", true}, {"removal_time_s", 0.2}, {"removal_distance_m", 0.002},
        {"max_settling_time_s", 0.05}, {"plate_speed_m_per_s", 0.002}, {"target_axial_strain", 0.02}, {"sample_interval_s", 0.001}};
    ServerProcess server(tmp.path() / "data", {"--runner", WIREDEM_CLIENT_BIN, "--jobs", "1", "--threads-per-job", "1",
        "--checkpoint-seconds", "0.05", "--max-steps-per-job", "1e8"});
    const auto r = http(server.port(), "POST", "/v1/jobs", json::serialize(spec));
    ASSERT_EQ(r.status, 201) << r.body;
    const std::string id(r.json().at("id").as_string());
    const std::string route = "/v1/jobs/" + id + "/free_standing";
    const std::string series = route + "/series?columns=time_s,sigma1_pa,phase"; // named, from before the test begins

    std::vector<json::value> partial;  // each reply that had grown
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    for (;;) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        const json::value job = http(server.port(), "GET", "/v1/jobs/" + id).json();
        if (state_of(job) == "succeeded") break;
        ASSERT_TRUE(state_of(job) == "queued" || state_of(job) == "preparing" || state_of(job) == "running") << server.log();
        ASSERT_LT(std::chrono::steady_clock::now(), deadline) << server.log();
        const auto reply = http(server.port(), "GET", series);
        if (reply.status == 409) continue;  // queued, or succeeded meanwhile
        ASSERT_EQ(reply.status, 200) << reply.body;
        const json::value s = reply.json();
        if (!s.at("partial").as_bool()) continue;  // finished already
        const std::size_t rows = s.at("rows").to_number<std::size_t>();
        if (rows == 0) continue;  // waiting, or running before its first checkpoint
        EXPECT_EQ(s.at("state"), "running");
        EXPECT_EQ(s.at("reached").at("rows").to_number<std::size_t>(), rows);
        EXPECT_EQ(s.at("reached").at("time_s").to_number<double>(), column_of(s, "time_s").back());
        if (partial.empty() || rows > partial.back().at("rows").to_number<std::size_t>()) partial.push_back(s);
        const auto test_reply = http(server.port(), "GET", route);
        ASSERT_EQ(test_reply.status, 200) << test_reply.body;
        const json::value t = test_reply.json();
        if (t.at("state") == "running") {
            EXPECT_TRUE(t.at("partial").as_bool()) << test_reply.body;
        }
    }
    ASSERT_GE(partial.size(), 2u) << "the series should have grown at least once while the test ran";

    const auto done = http(server.port(), "GET", series);
    ASSERT_EQ(done.status, 200);
    expect_partials_begin_the_final_series(done.json(), partial, {"time_s", "sigma1_pa", "phase"});
}

} // namespace
} // namespace wiredem::test

namespace wiredem::test {
namespace {

// The data routes read HDF5 and serialise JSON off the I/O threads: with one
// I/O thread, a series of a million rows (a second or more to read and
// serialise) does not hold up a status request sent meanwhile. Before, on the
// I/O thread, the status request waited for the whole read.
TEST(ResultDataThreads, ALargeReadDoesNotHoldUpOtherRequests)
{
    TempDir tmp;
    const std::filesystem::path made = tmp.path() / "made";
    std::filesystem::create_directories(made);
    {
        constexpr std::size_t big = 1'000'000;
        io::File file = io::File::create(made / "result.h5");
        io::Group t = file.root().create_group("tests/sigma3_1000");
        t.write_double_attribute("confining_pressure_pa", 1000.0);
        std::vector<double> v(big);
        for (const char* c : {"time_s", "axial_strain", "deviatoric_stress_pa"}) {
            for (std::size_t i = 0; i < big; ++i) v[i] = std::sqrt(static_cast<double>(i) + c[0]);
            t.write_dataset(c, std::span<const double>(v));
        }
    }
    ::setenv("WIREDEM_FAKE_RESULT_DIR", made.c_str(), 1);
    ServerProcess server(tmp.path() / "data", {"--io-threads", "1"}, 0.02);
    ::unsetenv("WIREDEM_FAKE_RESULT_DIR");
    const auto res = http(server.port(), "POST", "/v1/jobs", R"({"name": "big"})");
    ASSERT_EQ(res.status, 201) << res.body;
    const std::string id(res.json().at("id").get_string());
    ASSERT_EQ(state_of(poll_job(server.port(), id, [](const json::value& j) { return state_of(j) == "succeeded"; })), "succeeded");

    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    auto large = std::async(std::launch::async, [&] {
        const auto r = http(server.port(), "GET", "/v1/jobs/" + id + "/tests/sigma3_1000/series");
        return std::pair{r.status, clock::now()};
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the read under way
    const auto t1 = clock::now();
    EXPECT_EQ(http(server.port(), "GET", "/v1/health").status, 200);
    const auto t2 = clock::now();
    const auto [status, t3] = large.get();
    ASSERT_EQ(status, 200);
    const double read_ms = std::chrono::duration<double, std::milli>(t3 - t0).count();
    const double status_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
    std::printf("[ threads  ] a series of 1e6 rows took %.0f ms; a status request sent 100 ms into it, %.1f ms\n",
        read_ms, status_ms);
    ASSERT_GT(read_ms, 400.0) << "the large read was too quick to tell anything";
    EXPECT_LT(t2, t3) << "the status request waited for the large read";
    EXPECT_LT(status_ms, 0.25 * read_ms);
}

} // namespace
} // namespace wiredem::test

// The free-standing test's routes (handlers/results.hpp) against a result.h5
// whose /free_standing group campaign::write_free_standing_result wrote from
// a record with known values: the readings, the series, the radius profiles,
// the wire at the largest σ₁ and the snapshots come back as written; a job
// without the test has no such route; while a job runs, the route says
// whether the test has begun and serves it once its file is there.
namespace wiredem::test {
namespace {

constexpr std::size_t fs_rows = 40;
constexpr std::size_t fs_segments = 12;

/// Row i of the free-standing series: phase by quarters, σ₁ distinct per row.
engine::FreeStandingResult free_standing_record()
{
    engine::FreeStandingResult r;
    for (std::size_t i = 0; i < fs_rows; ++i) {
        engine::TriaxialSample s;
        s.time_s = 1e-3 * static_cast<double>(i);
        s.phase = static_cast<engine::TriaxialPhase>(std::min<std::size_t>(3, i / 10));
        s.axial_strain = i < 30 ? 0.0 : 0.01 * static_cast<double>(i - 30);
        s.sigma1_pa = 1000.0 + 7.0 * static_cast<double>(i);
        r.series.push_back(s);
    }
    r.settling.at_rest = true;
    r.settling.stands = true;
    r.settling.height_loss = 0.0125;
    r.settling.bulk_height_before_m = 0.05;
    r.settling.bulk_height_m = 0.045;
    r.settling.bulk_height_loss = 0.1;
    r.settling.grains = 150;
    r.settling.escaped_grains = 6;
    r.settling.lost_fraction = 0.0375;
    r.settling.profile_before = {{0.001, 0.003}, {0.008, 0.0081}, {5, 6}};
    r.settling.profile = {{0.001, 0.003, 0.005}, {0.0085, 0.0086, 0.0079}, {4, 5, 2}};
    engine::CompressionReading c;
    c.strength.shape = engine::analysis::CurveShape::peak;
    c.strength.index = 35;
    c.strength.value = 1234.5;
    c.max_sigma1_pa = 1273.0;
    c.max_sigma1_sample = 39;
    c.profile_at_peak = {{0.002}, {0.0095}, {9}};
    c.profile_at_end = {{0.002}, {0.0101}, {8}};
    for (std::size_t k = 0; k < fs_segments; ++k) {
        c.wire_strain_at_peak.push_back(1e-4 * static_cast<double>(k));
        c.wire_tension_at_peak_n.push_back(0.5 * static_cast<double>(k));
    }
    r.compression = c;
    r.loading_start_sample = 30;
    engine::TriaxialSnapshot snap;
    snap.requested_axial_strain = 0.05;
    snap.axial_strain = 0.0501;
    snap.grain_position_m = {{0.001, 0.002, 0.003}, {0.004, 0.005, 0.006}};
    snap.grain_radius_m = {1e-3, 1e-3};
    r.snapshots.push_back(snap);
    r.peak_snapshot = snap;
    return r;
}

/// result.h5 with a specimen, no triaxial test and the free-standing test;
/// the same group alone as the runner's tests/free_standing.h5.
void write_free_standing_files(const fs::path& dir)
{
    fs::create_directories(dir);
    {
        io::File file = io::File::create(dir / "result.h5");
        io::Group root = file.root();
        root.write_string_attribute("format", "wiredem-result-1");
        root.write_string_dataset("job_spec", R"({"name": "slow free", "free_standing": {"enabled": true}})");
        io::Group g = root.create_group(campaign::free_standing_group);
        campaign::write_free_standing_result(g, free_standing_record());
    }
    io::File file = io::File::create(dir / "free_standing.h5");
    io::Group g = file.root().create_group(campaign::free_standing_group);
    campaign::write_free_standing_result(g, free_standing_record());
}

class FreeStandingData : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        tmp_ = new TempDir;
        write_free_standing_files(tmp_->path() / "made");
        ::setenv("WIREDEM_FAKE_RESULT_DIR", (tmp_->path() / "made").c_str(), 1);
        server_ = new ServerProcess(tmp_->path() / "data", {}, 0.02);
        ::unsetenv("WIREDEM_FAKE_RESULT_DIR");
        // "slow": the fake runner hands its free_standing.h5 over three quarters through its steps.
        const auto res = http(server_->port(), "POST", "/v1/jobs",
            R"({"name": "slow free", "specimen": {"wire": {"segment_length_m": )" + std::to_string(segment_length_m)
                + R"(}}, "free_standing": {"enabled": true}})");
        ASSERT_EQ(res.status, 201) << res.body;
        id_ = std::string(res.json().at("id").get_string());
        // While it runs: waiting (or running) first, then finished with the file's rows.
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        json::value job;
        for (;;) {
            job = http(server_->port(), "GET", "/v1/jobs/" + id_).json();
            const std::string state = state_of(job);
            if (state == "succeeded" || state == "failed" || std::chrono::steady_clock::now() > deadline) break;
            if (state == "running") {
                // The job may succeed between two requests: a reply without
                // "state" is the succeeded job's (checked by the tests below).
                const auto fs = get("/free_standing");
                const json::value b = fs.status == 200 ? fs.json() : json::value();
                const json::value* fs_state = b.is_object() ? b.as_object().if_contains("state") : nullptr;
                if (fs_state) {
                    const std::string now(fs_state->get_string());
                    if (now != "finished") {
                        EXPECT_EQ(b.at("rows").to_number<std::size_t>(), 0u);
                        EXPECT_TRUE(b.at("partial").as_bool());
                        const auto series = get("/free_standing/series");
                        EXPECT_EQ(series.status, 200) << series.body;
                        const json::value sb = series.json();
                        if (sb.as_object().contains("state") && sb.at("state") != "finished") {
                            EXPECT_EQ(sb.at("rows").to_number<std::size_t>(), 0u);
                        }
                        // Named columns are answered before the first row too (it answered 400).
                        const auto named = get("/free_standing/series?columns=phase,sigma1_pa");
                        EXPECT_EQ(named.status, 200) << named.body;
                        if (named.status == 200 && named.json().as_object().contains("state")
                            && named.json().at("state") != "finished") {
                            EXPECT_EQ(named.json().at("columns").as_object().size(), 2u) << named.body;
                        }
                    } else {
                        EXPECT_EQ(b.at("rows").to_number<std::size_t>(), fs_rows);
                        EXPECT_FALSE(b.at("partial").as_bool());
                        const auto snap = get("/free_standing/snapshots/0");
                        if (snap.status != 409) {
                            EXPECT_EQ(state_of(http(server_->port(), "GET", "/v1/jobs/" + id_).json()), "succeeded")
                                << "snapshots only once the job has succeeded";
                        }
                    }
                    live_states_.insert(now);
                }
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        ASSERT_EQ(state_of(job), "succeeded") << server_->log();
    }
    static void TearDownTestSuite()
    {
        delete server_;
        delete tmp_;
    }
    static RawReply get(const std::string& path) { return http(server_->port(), "GET", "/v1/jobs/" + id_ + path); }

    static inline TempDir* tmp_ = nullptr;
    static inline ServerProcess* server_ = nullptr;
    static inline std::string id_;
    static inline std::set<std::string> live_states_;
};

TEST_F(FreeStandingData, TheTestIsServedWithItsReadingsProfilesAndWireAsWritten)
{
    const auto res = get("/free_standing");
    ASSERT_EQ(res.status, 200) << res.body;
    const json::value b = res.json();
    EXPECT_EQ(b.at("name").get_string(), "free_standing");
    EXPECT_FALSE(b.at("partial").as_bool());
    EXPECT_EQ(b.at("rows").to_number<std::size_t>(), fs_rows);
    const auto& a = b.at("attributes");
    EXPECT_EQ(a.at("stands").to_number<int>(), 1);
    EXPECT_DOUBLE_EQ(a.at("height_loss").to_number<double>(), 0.0125);
    // What the verdict reads: the grains' bulk and the grains lost.
    EXPECT_DOUBLE_EQ(a.at("bulk_height_before_m").to_number<double>(), 0.05);
    EXPECT_DOUBLE_EQ(a.at("bulk_height_m").to_number<double>(), 0.045);
    EXPECT_DOUBLE_EQ(a.at("bulk_height_loss").to_number<double>(), 0.1);
    EXPECT_EQ(a.at("grains").to_number<int>(), 150);
    EXPECT_EQ(a.at("escaped_grains").to_number<int>(), 6);
    EXPECT_DOUBLE_EQ(a.at("lost_fraction").to_number<double>(), 0.0375);
    EXPECT_EQ(a.at("strength_shape").get_string(), "peak");
    EXPECT_DOUBLE_EQ(a.at("strength_smoothed_maximum").to_number<double>(), 1234.5);
    // The columns are the series' (not the wire's per-segment arrays, not the underived ε_v).
    std::vector<std::string> columns;
    for (const auto& c : b.at("columns").as_array()) columns.emplace_back(c.at("name").get_string());
    for (const char* c : {"time_s", "axial_strain", "sigma1_pa", "phase"})
        EXPECT_NE(std::find(columns.begin(), columns.end(), c), columns.end()) << c;
    for (const char* c : {"wire_strain_at_peak", "wire_tension_at_peak_n", "volumetric_strain"})
        EXPECT_EQ(std::find(columns.begin(), columns.end(), c), columns.end()) << c;
    // Radius profiles: radius against height, as written.
    const auto& settled = b.at("profiles").at("profile_settled");
    ASSERT_EQ(settled.at("height_m").as_array().size(), 3u);
    EXPECT_DOUBLE_EQ(settled.at("radius_m").at(1).to_number<double>(), 0.0086);
    EXPECT_EQ(settled.at("grains").at(2).to_number<int>(), 2);
    EXPECT_DOUBLE_EQ(b.at("profiles").at("profile_at_peak").at("radius_m").at(0).to_number<double>(), 0.0095);
    EXPECT_DOUBLE_EQ(b.at("profiles").at("profile_before").at("height_m").at(1).to_number<double>(), 0.003);
    // The wire at the largest σ₁: along its length at the spec's l_w.
    const auto& w = b.at("wire_at_peak");
    ASSERT_EQ(w.at("tension_n").as_array().size(), fs_segments);
    EXPECT_DOUBLE_EQ(w.at("tension_n").at(5).to_number<double>(), 2.5);
    EXPECT_DOUBLE_EQ(w.at("strain").at(5).to_number<double>(), 5e-4);
    EXPECT_DOUBLE_EQ(w.at("distance_m").at(5).to_number<double>(), 5.5 * segment_length_m);
    EXPECT_EQ(b.at("snapshots").as_array().size(), 1u);
    EXPECT_EQ(b.at("peak_snapshot").at("url").get_string(), "/v1/jobs/" + id_ + "/free_standing/peak_snapshot");
}

TEST_F(FreeStandingData, ItsSeriesHoldTheRecordsRowsAndTakeTheTestsParameters)
{
    const auto all = get("/free_standing/series?columns=phase,sigma1_pa");
    ASSERT_EQ(all.status, 200) << all.body;
    const json::value b = all.json();
    EXPECT_EQ(b.at("rows").to_number<std::size_t>(), fs_rows);
    for (std::size_t i = 0; i < fs_rows; ++i) {
        EXPECT_DOUBLE_EQ(b.at("columns").at("sigma1_pa").at(i).to_number<double>(), 1000.0 + 7.0 * static_cast<double>(i));
        EXPECT_EQ(b.at("columns").at("phase").at(i).to_number<int>(), static_cast<int>(std::min<std::size_t>(3, i / 10)));
    }
    EXPECT_EQ(b.at("units").at("phase").get_string(), "0 removal, 1 settling, 2 dead_load, 3 loading");
    const auto thin = get("/free_standing/series?max_points=2");
    ASSERT_EQ(thin.status, 200) << thin.body;
    EXPECT_EQ(thin.json().at("returned_rows").to_number<std::size_t>(), 2u);
    EXPECT_EQ(get("/free_standing/series?columns=wire_tension_at_peak_n").error_code(), "bad_parameter");
    EXPECT_EQ(get("/free_standing/series?bogus=1").error_code(), "bad_parameter");
    EXPECT_EQ(get("/free_standing?max_points=3").error_code(), "bad_parameter");
}

TEST_F(FreeStandingData, ItsSnapshotsAndThePeakOneAreServedAsATestsAre)
{
    const auto snap = get("/free_standing/snapshots/0");
    ASSERT_EQ(snap.status, 200) << snap.body;
    EXPECT_DOUBLE_EQ(snap.json().at("attributes").at("axial_strain").to_number<double>(), 0.0501);
    const auto peak = get("/free_standing/peak_snapshot/grain_position_m");
    ASSERT_EQ(peak.status, 200) << peak.body;
    EXPECT_EQ(peak.headers.at("x-wiredem-shape"), "2,3");
    ASSERT_EQ(peak.body.size(), 6 * sizeof(float));
    float first = 0;
    std::memcpy(&first, peak.body.data(), sizeof first);
    EXPECT_FLOAT_EQ(first, 0.001f);
    EXPECT_EQ(get("/free_standing/snapshots/1").status, 404);
    EXPECT_EQ(get("/free_standing/peak_snapshot/nothing").status, 404);
    EXPECT_EQ(get("/free_standing/other").status, 404);
}

TEST_F(FreeStandingData, WhileTheJobRanTheRouteSaidWhetherTheTestHadFinished)
{
    EXPECT_TRUE(live_states_.count("finished")) << "the runner's tests/free_standing.h5 was served while the job ran";
    EXPECT_TRUE(live_states_.count("waiting") || live_states_.count("running")) << "and before it, the test's state";
}

TEST_F(FreeStandingData, AJobWithoutTheTestHasNoRoute)
{
    const auto res = http(server_->port(), "POST", "/v1/jobs", R"({"name": "no free-standing"})");
    ASSERT_EQ(res.status, 201);
    const std::string id(res.json().at("id").get_string());
    const auto res2 = http(server_->port(), "GET", "/v1/jobs/" + id + "/free_standing");
    EXPECT_EQ(res2.status, 404) << res2.body;
    const json::value doc = http(server_->port(), "GET", "/v1/openapi.json").json();
    for (const char* p : {"/v1/jobs/{id}/free_standing", "/v1/jobs/{id}/free_standing/series",
             "/v1/jobs/{id}/free_standing/snapshots/{k}", "/v1/jobs/{id}/free_standing/peak_snapshot"})
        EXPECT_TRUE(doc.at("paths").as_object().contains(p)) << p;
}

} // namespace
} // namespace wiredem::test
