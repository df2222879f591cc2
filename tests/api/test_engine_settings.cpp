// The job spec → engine settings mapping (api/engine_settings): what the
// runner executes is what the job asked for.
#include "api/engine_settings.hpp"
#include "api/job_spec.hpp"
#include "specimen/pattern.hpp"

#include <gtest/gtest.h>

using namespace wiredem;

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
    EXPECT_EQ(api::preparation_spec(parse("{}")).membrane.edge_law, engine::MembraneEdgeLaw::tension_only);
    EXPECT_EQ(api::preparation_spec(parse(R"({"specimen": {"membrane": {"edges": "linear"}}})")).membrane.edge_law,
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

// specimen.wire.pattern is read into the engine's own PatternKind: the job
// spec's names for it are the engine's (engine::pattern_name), so that a
// message, a stored spec and the engine name a pattern alike, and each name
// reads back as its kind.
TEST(EngineSettings, TheWirePatternsJsonNamesAreTheEnginesOwn)
{
    for (const engine::PatternKind k : {engine::PatternKind::none, engine::PatternKind::helix,
             engine::PatternKind::spiral_helix, engine::PatternKind::radial_helix, engine::PatternKind::toolpath}) {
        EXPECT_EQ(api::to_string(k), engine::pattern_name(k));
        engine::PatternKind back{};
        ASSERT_TRUE(engine::parse_pattern_kind(api::to_string(k), back)) << api::to_string(k);
        EXPECT_EQ(back, k);
    }
}
