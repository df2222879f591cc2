// The job spec → engine settings mapping (api/engine_settings): what the
// runner executes is what the job asked for.
#include "api/engine_settings.hpp"
#include "api/job_spec.hpp"
#include "specimen/pattern.hpp"
#include "triaxial/consolidation.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <string>
#include <string_view>

using namespace wiredem;
namespace json = boost::json;

namespace {

api::JobSpec parse(std::string_view text)
{
    auto r = api::parse_job_spec(text);
    EXPECT_TRUE(r.ok());
    return r.value();
}

} // namespace

TEST(EngineSettings, IntegratorReachesThePreparationAndSoEveryTest)
{
    EXPECT_EQ(api::preparation_spec(parse("{}")).integrator, engine::Integrator::gear5);
    EXPECT_EQ(api::preparation_spec(parse(R"({"engine": {"integrator": "verlet"}})")).integrator,
        engine::Integrator::verlet);
}

TEST(EngineSettings, MembraneEdgeLawReachesThePreparation)
{
    EXPECT_EQ(api::preparation_spec(parse("{}")).membrane.edges, engine::MembraneEdgeLaw::tension_only);
    EXPECT_EQ(api::preparation_spec(parse(R"({"specimen": {"membrane": {"edges": "linear"}}})")).membrane.edges,
        engine::MembraneEdgeLaw::linear);
}

TEST(EngineSettings, TimeStepSeedAndScalingArePassedThrough)
{
    const api::JobSpec spec = parse(R"({"seed": 42, "engine": {"time_step_s": 2e-7, "density_scale": 10}})");
    const engine::PreparationSpec p = api::preparation_spec(spec);
    EXPECT_EQ(p.seed, 42u);
    EXPECT_EQ(p.time_step_s, 2e-7);
    EXPECT_EQ(p.density_scale, 10.0);
    EXPECT_EQ(api::preparation_spec(parse("{}")).time_step_s, 0.0); // auto
}

// The enums of the spec are the engine's own (PatternKind, Integrator,
// MembraneEdgeLaw, Consolidation, SieveBasis, WireEnd), read through the
// engine's one name table of each (engine/core/name_table.hpp), so that a
// message, a stored spec and the engine name a value alike: for every
// field, the schema offers exactly the engine's names in its order, each name
// reads into the engine's value and is written back as itself, and a name
// that is not the engine's is refused at that field.
namespace {

/// The field at `path` (dots) of the job spec's JSON Schema: through
/// "properties", and through the alternatives of a nullable object.
const json::object* schema_field(const json::object& schema, std::string_view path)
{
    const json::object* at = &schema;
    while (!path.empty()) {
        const std::size_t dot = path.find('.');
        const std::string key(path.substr(0, dot));
        path = dot == std::string_view::npos ? std::string_view{} : path.substr(dot + 1);
        const json::object* next = nullptr;
        const auto in = [&](const json::object& o) {
            if (const json::value* p = o.if_contains("properties"); p && p->is_object())
                if (const json::value* f = p->as_object().if_contains(key); f && f->is_object()) next = &f->as_object();
        };
        in(*at);
        for (const char* alt : {"anyOf", "oneOf"})
            if (const json::value* a = at->if_contains(alt); !next && a && a->is_array())
                for (const json::value& o : a->as_array())
                    if (!next && o.is_object()) in(o.as_object());
        if (!next) return nullptr;
        at = next;
    }
    return at;
}

const json::value* json_at(const json::value& doc, std::string_view path)
{
    const json::value* at = &doc;
    while (!path.empty()) {
        const std::size_t dot = path.find('.');
        if (!at->is_object()) return nullptr;
        at = at->as_object().if_contains(path.substr(0, dot));
        if (!at) return nullptr;
        path = dot == std::string_view::npos ? std::string_view{} : path.substr(dot + 1);
    }
    return at;
}

/// `document(name)` is a valid spec with `name` at `path`; `field` reads the
/// parsed value.
template <class E, std::size_t N, class Document, class Field>
void expect_json_names_are_the_engines(std::string_view path, const engine::NameTable<E, N>& engine_names,
    Document document, Field field)
{
    SCOPED_TRACE(std::string(path));
    const json::object whole = api::job_spec_json_schema();
    const json::object* schema = schema_field(whole, path);
    ASSERT_NE(schema, nullptr) << "no field " << path << " in the schema";
    const json::value* offered = schema->if_contains("enum");
    ASSERT_TRUE(offered && offered->is_array()) << json::serialize(*schema);
    ASSERT_EQ(offered->as_array().size(), N) << json::serialize(*offered);
    for (std::size_t i = 0; i < N; ++i) {
        const auto& [name, value] = engine_names[i];
        EXPECT_EQ(offered->as_array()[i], json::value(json::string(name))) << "the schema offers another name";
        EXPECT_EQ(api::to_string(value), name);
        const auto r = api::parse_job_spec(document(name));
        ASSERT_TRUE(r.ok()) << name << ": " << (r.ok() ? "" : r.error().front().path + ": " + r.error().front().message);
        EXPECT_EQ(field(r.value()), value) << name << " read as another value";
        const json::value whole_written = api::to_json(r.value()); // json_at points into it
        const json::value* written = json_at(whole_written, path);
        ASSERT_NE(written, nullptr);
        EXPECT_EQ(*written, json::value(json::string(name))) << "written as another name";
    }
    const std::string other = std::string(engine_names[0].first) + "_not_the_engines";
    const auto refused = api::parse_job_spec(document(other));
    ASSERT_FALSE(refused.ok()) << other << " was accepted";
    EXPECT_EQ(refused.error().front().path, path);
}

std::string nested(std::string_view path, std::string_view name, std::string_view sibling_fields = "")
{
    // {"a": {"b": {"c": "name", sibling_fields}}} for path a.b.c
    std::string open, close;
    std::string_view rest = path;
    while (true) {
        const std::size_t dot = rest.find('.');
        if (dot == std::string_view::npos) break;
        open += "{\"" + std::string(rest.substr(0, dot)) + "\": ";
        close += "}";
        rest = rest.substr(dot + 1);
    }
    std::string leaf = "{\"" + std::string(rest) + "\": \"" + std::string(name) + "\"";
    if (!sibling_fields.empty()) leaf += ", " + std::string(sibling_fields);
    return open + leaf + "}" + close;
}

} // namespace

TEST(EngineSettings, TheWirePatternsJsonNamesAreTheEnginesOwn)
{
    // A toolpath needs its points; the other patterns take none.
    expect_json_names_are_the_engines("specimen.wire.pattern", engine::pattern_kind_names,
        [](std::string_view n) {
            return n == "toolpath" ? nested("specimen.wire.pattern", n, R"("toolpath_x_m": [0.004, -0.004], "toolpath_y_m": [0, 0])")
                                   : nested("specimen.wire.pattern", n);
        },
        [](const api::JobSpec& s) { return s.specimen.wire.pattern; });
    for (const auto& [name, kind] : engine::pattern_kind_names) {
        EXPECT_EQ(engine::pattern_name(kind), name);
        engine::PatternKind back{};
        ASSERT_TRUE(engine::parse_pattern_kind(name, back)) << name;
        EXPECT_EQ(back, kind);
    }
}

TEST(EngineSettings, TheIntegratorsJsonNamesAreTheEnginesOwn)
{
    expect_json_names_are_the_engines("engine.integrator", engine::integrator_names,
        [](std::string_view n) { return nested("engine.integrator", n); },
        [](const api::JobSpec& s) { return s.engine.integrator; });
}

TEST(EngineSettings, TheMembraneEdgesJsonNamesAreTheEnginesOwn)
{
    expect_json_names_are_the_engines("specimen.membrane.edges", engine::membrane_edge_law_names,
        [](std::string_view n) { return nested("specimen.membrane.edges", n); },
        [](const api::JobSpec& s) { return s.specimen.membrane.edges; });
}

TEST(EngineSettings, TheConsolidationsJsonNamesAreTheEnginesOwn)
{
    expect_json_names_are_the_engines("triaxial.consolidation", engine::consolidation_names,
        [](std::string_view n) { return nested("triaxial.consolidation", n); },
        [](const api::JobSpec& s) { return s.triaxial.consolidation; });
    // The name result.h5 and summary.json carry is the same (campaign/files.cpp).
    for (const auto& [name, value] : engine::consolidation_names)
        EXPECT_EQ(engine::consolidation_from_string(name), value);
}

TEST(EngineSettings, TheGrainSizeBasesJsonNamesAreTheEnginesOwn)
{
    expect_json_names_are_the_engines("specimen.grain_sizes.basis", engine::sieve_basis_names,
        [](std::string_view n) {
            return nested("specimen.grain_sizes.basis", n, R"("diameters_m": [2e-3, 3e-3], "fraction_passing": [0, 1])");
        },
        [](const api::JobSpec& s) { return s.specimen.grain_sizes->basis; });
}

TEST(EngineSettings, TheWireEndsJsonNamesAreTheEnginesOwn)
{
    expect_json_names_are_the_engines("free_standing.pull_out_end", engine::wire_end_names,
        // Another field off its default, so that to_json writes the block ("last" is the default).
        [](std::string_view n) { return nested("free_standing.pull_out_end", n, R"("removal_time_s": 0.03)"); },
        [](const api::JobSpec& s) { return s.free_standing.pull_out_end; });
}
