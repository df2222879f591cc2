// The summary a real campaign writes against the Summary schema the server
// serves (/v1/openapi.json): every key declared, every declared-required key
// present, every value of its type, in its enum, null only where nullable.
// The schema is written by hand (server/handlers/meta.cpp) and the summary
// by campaign/stages.cpp: this keeps them one description.
#include "harness.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace wiredem::test {
namespace {
namespace json = boost::json;

/// Where a value disagrees with its schema, by JSON path ("$.tests[0].yield").
struct Failure {
    std::string path;
    std::string what;
};

/// The OpenAPI 3.0 subset the document's schemas use, checked closed: an
/// object may hold only the keys its `properties` declare, and a keyword
/// this check does not understand is itself a failure, so that a schema
/// it cannot judge is never passed. Types as the JSON text gave them:
/// "integer" is a number written without fraction or exponent (a count
/// written as 3E3 would break a client reading it as an integer).
class SchemaCheck {
public:
    explicit SchemaCheck(const json::value& document) : doc_(document) {}

    std::vector<Failure> operator()(const json::value& v, const json::value& schema)
    {
        failures_.clear();
        check(v, schema, "$");
        return failures_;
    }

private:
    const json::object& resolve(const json::value& schema) const
    {
        const json::object* s = &schema.as_object();
        // "#/components/…": a JSON pointer into the document (references to references too).
        while (const json::value* ref = s->if_contains("$ref")) s = &doc_.at_pointer(std::string(ref->as_string()).substr(1)).as_object();
        return *s;
    }

    static bool has_type(const json::value& v, std::string_view type)
    {
        if (type == "number") return v.is_number();
        if (type == "integer") return v.is_int64() || v.is_uint64();
        if (type == "string") return v.is_string();
        if (type == "boolean") return v.is_bool();
        if (type == "array") return v.is_array();
        if (type == "object") return v.is_object();
        return false;
    }

    void fail(const std::string& path, std::string what) { failures_.push_back({path, std::move(what)}); }

    void check(const json::value& v, const json::value& schema_value, const std::string& path)
    {
        const json::object& s = resolve(schema_value);
        static const std::set<std::string_view> understood{"type", "nullable", "enum", "properties", "required", "items",
            "description", "default", "example"};
        for (const auto& [keyword, _] : s)
            if (!understood.contains(keyword)) fail(path, "schema keyword " + std::string(keyword) + " is not checked here");

        if (v.is_null()) {
            const json::value* nullable = s.if_contains("nullable");
            if (!(nullable && nullable->as_bool())) fail(path, "null, but not nullable");
            return;
        }
        if (const json::value* type = s.if_contains("type"); type && !has_type(v, type->as_string())) {
            fail(path, json::serialize(v) + " is not of type " + std::string(type->as_string()));
            return;
        }
        if (const json::value* values = s.if_contains("enum")) {
            const json::array& e = values->as_array();
            if (std::find(e.begin(), e.end(), v) == e.end()) fail(path, json::serialize(v) + " is not one of " + json::serialize(e));
        }
        if (const json::object* o = v.if_object()) {
            static const json::object none;
            const json::value* declared = s.if_contains("properties");
            const json::object& properties = declared ? declared->as_object() : none;
            for (const auto& [key, value] : *o) {
                const std::string at = path + "." + std::string(key);
                if (const json::value* p = properties.if_contains(key)) check(value, *p, at);
                else fail(at, "not declared in the schema");
            }
            if (const json::value* required = s.if_contains("required"))
                for (const json::value& key : required->as_array())
                    if (!o->contains(key.as_string())) fail(path + "." + std::string(key.as_string()), "required, but absent");
        }
        if (const json::array* a = v.if_array(); a && s.contains("items"))
            for (std::size_t i = 0; i < a->size(); ++i) check((*a)[i], s.at("items"), path + "[" + std::to_string(i) + "]");
    }

    const json::value& doc_;
    std::vector<Failure> failures_;
};

std::string listed(const std::vector<Failure>& failures)
{
    std::string out;
    for (const Failure& f : failures) out += f.path + ": " + f.what + "\n";
    return out;
}

std::set<std::string> paths_of(const std::vector<Failure>& failures)
{
    std::set<std::string> out;
    for (const Failure& f : failures) out.insert(f.path);
    return out;
}

// The check on a small document: each kind of disagreement is found, at its path.
TEST(SummarySchema, TheCheckFindsEachKindOfDisagreementAtItsPath)
{
    const json::value doc = json::parse(R"({"components": {"schemas": {
        "Top": {"type": "object", "required": ["n", "list"], "properties": {
            "n": {"type": "integer"}, "x": {"type": "number", "nullable": true},
            "list": {"type": "array", "items": {"$ref": "#/components/schemas/Item"}}}},
        "Item": {"type": "object", "required": ["kind"], "properties": {
            "kind": {"type": "string", "nullable": true, "enum": ["a", "b", null]}, "flag": {"type": "boolean"}}}}}})");
    SchemaCheck check(doc);
    const json::value& top = doc.at_pointer("/components/schemas/Top");

    EXPECT_EQ(listed(check(json::parse(R"({"n": 3, "x": null, "list": [{"kind": "a"}, {"kind": null, "flag": true}]})"), top)), "");
    const auto failures = check(
        json::parse(R"({"n": 3E0, "x": "1", "list": [{"kind": "c"}, {"flag": null}, {"kind": "a", "more": 1}]})"), top);
    EXPECT_EQ(paths_of(failures), (std::set<std::string>{"$.n", "$.x", "$.list[0].kind", "$.list[1].flag", "$.list[1].kind",
                                      "$.list[2].more"}))
        << listed(failures);
    EXPECT_EQ(failures.size(), 6u) << listed(failures);
    // A keyword it cannot judge fails rather than passes.
    EXPECT_EQ(listed(check(json::value(1), json::parse(R"({"type": "integer", "minimum": 2})"))),
        "$: schema keyword minimum is not checked here\n");
}

// A real campaign's summary, as GET /v1/jobs/{id}/summary gives it, against
// the schema of that route as /v1/openapi.json gives it. The job: the web
// test's (examples/tiny.json with a helix, a few seconds), so that the wire's
// figures are numbers, not the nulls of a column without wire.
TEST(SummarySchemaRealRunner, ARealCampaignsSummaryIsWhatTheOpenApiDocumentSays)
{
    namespace fs = std::filesystem;
    TempDir tmp;
    ServerProcess server(tmp.path() / "data",
        {"--runner", WIREDEM_CLIENT_BIN, "--jobs", "1", "--threads-per-job", "2", "--max-steps-per-job", "1e8"});
    // With a short free-standing test, so that its part of the summary is checked too.
    json::object spec = json::parse(read_file(fs::path(WIREDEM_SOURCE_DIR) / "tests/web/job.json")).as_object();
    spec["free_standing"] = json::object{{"enabled", true}, {"removal_time_s", 0.01}, {"removal_distance_m", 0.002},
        {"max_settling_time_s", 0.05}, {"dead_load_n", 0.05}, {"dead_load_hold_time_s", 0.01},
        {"plate_speed_m_per_s", 0.02}, {"target_axial_strain", 0.03}, {"sample_interval_s", 0.0005}};
    const auto r = http(server.port(), "POST", "/v1/jobs", json::serialize(spec));
    ASSERT_EQ(r.status, 201) << r.body;
    const std::string id(r.json().at("id").as_string());
    const auto job = poll_job(server.port(), id, [](const json::value& j) {
        const std::string s = state_of(j);
        return s == "succeeded" || s == "failed" || s == "cancelled";
    }, std::chrono::seconds(240));
    ASSERT_EQ(state_of(job), "succeeded") << json::serialize(job) << server.log();

    const json::value doc = http(server.port(), "GET", "/v1/openapi.json").json();
    const json::value& schema = doc.at_pointer(
        "/paths/~1v1~1jobs~1{id}~1summary/get/responses/200/content/application~1json/schema");
    const auto reply = http(server.port(), "GET", "/v1/jobs/" + id + "/summary");
    ASSERT_EQ(reply.status, 200) << reply.body;
    const json::value summary = reply.json();
    SchemaCheck check(doc);
    EXPECT_EQ(listed(check(summary, schema)), "") << reply.body;
    // The run went through the branches that give numbers, not nulls.
    EXPECT_TRUE(summary.at_pointer("/tests/0/yield").is_object());
    EXPECT_TRUE(summary.at_pointer("/wire/autocorrelation_lag_m").is_number()) << reply.body;
    EXPECT_TRUE(summary.at_pointer("/free_standing/dead_load").is_object()) << reply.body;
    for (const char* p : {"/free_standing/settling/bulk_height_m", "/free_standing/settling/bulk_height_loss",
             "/free_standing/settling/lost_fraction", "/free_standing/compression/spilled_fraction",
             "/free_standing/compression/bulge_m"})
        EXPECT_TRUE(summary.at_pointer(p).is_number()) << p << ": " << reply.body;
    EXPECT_TRUE(summary.at_pointer("/free_standing/compression/failure_mode").is_string()) << reply.body;
    // String length per volume (issue 39, item 4): the wire's length over the sample's volume.
    EXPECT_GT(summary.at_pointer("/specimen/wire_length_m").to_number<double>(), 0.0);
    EXPECT_DOUBLE_EQ(summary.at_pointer("/specimen/wire_length_per_volume_m_per_m3").to_number<double>(),
        summary.at_pointer("/specimen/wire_length_m").to_number<double>()
            / summary.at_pointer("/specimen/sample_volume_m3").to_number<double>());

    // A drift of the writer, one key more and one type changed: exactly those two.
    json::value drifted = summary;
    drifted.at_pointer("/tests/1").as_object()["yield_strain_energy_j"] = 1.5;
    drifted.at_pointer("/engine").as_object()["steps"] = 12345.0;
    const auto failures = check(drifted, schema);
    EXPECT_EQ(paths_of(failures), (std::set<std::string>{"$.tests[1].yield_strain_energy_j", "$.engine.steps"}))
        << listed(failures);
    EXPECT_EQ(failures.size(), 2u) << listed(failures);
}

// A breakable wire, cut every loop (issue 39): the summary's wire pieces,
// breaks and peak failures are what the OpenAPI document says, and the
// pieces are the wire less its cut segments.
TEST(SummarySchemaRealRunner, ABreakableCutWiresSummaryIsWhatTheOpenApiDocumentSays)
{
    namespace fs = std::filesystem;
    TempDir tmp;
    ServerProcess server(tmp.path() / "data",
        {"--runner", WIREDEM_CLIENT_BIN, "--jobs", "1", "--threads-per-job", "2", "--max-steps-per-job", "1e8"});
    json::object spec = json::parse(read_file(fs::path(WIREDEM_SOURCE_DIR) / "tests/web/job.json")).as_object();
    json::object& wire = spec["specimen"].as_object()["wire"].as_object();
    wire["breaking_strain"] = 0.05; // a polyamide string breaks at 15-30 %; 0.2 % shattered this wire in the pour
    wire["cut_every_loops"] = 1;
    spec["free_standing"] = json::object{{"enabled", true}, {"removal_time_s", 0.01}, {"removal_distance_m", 0.002},
        {"max_settling_time_s", 0.05}, {"plate_speed_m_per_s", 0.02}, {"target_axial_strain", 0.03},
        {"sample_interval_s", 0.0005}};
    const auto r = http(server.port(), "POST", "/v1/jobs", json::serialize(spec));
    ASSERT_EQ(r.status, 201) << r.body;
    const std::string id(r.json().at("id").as_string());
    const auto job = poll_job(server.port(), id, [](const json::value& j) {
        const std::string s = state_of(j);
        return s == "succeeded" || s == "failed" || s == "cancelled";
    }, std::chrono::seconds(240));
    ASSERT_EQ(state_of(job), "succeeded") << json::serialize(job) << server.log();
    const json::value doc = http(server.port(), "GET", "/v1/openapi.json").json();
    const json::value& schema = doc.at_pointer(
        "/paths/~1v1~1jobs~1{id}~1summary/get/responses/200/content/application~1json/schema");
    const auto reply = http(server.port(), "GET", "/v1/jobs/" + id + "/summary");
    ASSERT_EQ(reply.status, 200) << reply.body;
    const json::value summary = reply.json();
    SchemaCheck check(doc);
    EXPECT_EQ(listed(check(summary, schema)), "") << reply.body;
    const json::array& pieces = summary.at_pointer("/specimen/wire_pieces").as_array();
    const auto cuts = summary.at_pointer("/specimen/wire_cuts").to_number<std::int64_t>();
    EXPECT_GT(cuts, 0) << "the helix has turns to cut";
    EXPECT_EQ(static_cast<std::int64_t>(pieces.size()), 1 + cuts + summary.at_pointer("/specimen/wire_breaks_in_preparation").to_number<std::int64_t>());
    std::int64_t nodes = 0;
    for (const json::value& p : pieces) nodes += p.at("nodes").to_number<std::int64_t>();
    EXPECT_EQ(nodes, summary.at_pointer("/specimen/wire_nodes").to_number<std::int64_t>()) << "every node is in one piece";
    for (const json::value& t : summary.at("tests").as_array()) {
        EXPECT_TRUE(t.at("wire_breaks").is_array());
        EXPECT_TRUE(t.at("peak_failure").is_string());
    }
    EXPECT_TRUE(summary.at_pointer("/free_standing/compression/wire_breaks").is_array()) << reply.body;
}

// A job with a grain-size curve (examples/tiny-graded.json): its summary's
// specimen.grain_sizes too is what the document says.
TEST(SummarySchemaRealRunner, AGradedCampaignsGrainSizesAreWhatTheOpenApiDocumentSays)
{
    namespace fs = std::filesystem;
    TempDir tmp;
    ServerProcess server(tmp.path() / "data",
        {"--runner", WIREDEM_CLIENT_BIN, "--jobs", "1", "--threads-per-job", "2", "--max-steps-per-job", "1e8"});
    const auto r = http(server.port(), "POST", "/v1/jobs", read_file(fs::path(WIREDEM_SOURCE_DIR) / "examples/tiny-graded.json"));
    ASSERT_EQ(r.status, 201) << r.body;
    const std::string id(r.json().at("id").as_string());
    const auto job = poll_job(server.port(), id, [](const json::value& j) {
        const std::string s = state_of(j);
        return s == "succeeded" || s == "failed" || s == "cancelled";
    }, std::chrono::seconds(240));
    ASSERT_EQ(state_of(job), "succeeded") << json::serialize(job) << server.log();
    const json::value doc = http(server.port(), "GET", "/v1/openapi.json").json();
    const json::value& schema = doc.at_pointer(
        "/paths/~1v1~1jobs~1{id}~1summary/get/responses/200/content/application~1json/schema");
    const auto reply = http(server.port(), "GET", "/v1/jobs/" + id + "/summary");
    ASSERT_EQ(reply.status, 200) << reply.body;
    const json::value summary = reply.json();
    SchemaCheck check(doc);
    EXPECT_EQ(listed(check(summary, schema)), "") << reply.body;
    ASSERT_TRUE(summary.at_pointer("/specimen/grain_sizes/drawn/d50_m").is_number()) << reply.body;
    // The 150 grains drawn pass the Kolmogorov–Smirnov test at 1 %.
    EXPECT_LT(summary.at_pointer("/specimen/grain_sizes/ks_distance").to_number<double>(),
        summary.at_pointer("/specimen/grain_sizes/ks_critical_1pct").to_number<double>());
}

} // namespace
} // namespace wiredem::test
