// The job spec → engine settings mapping (api/engine_settings): what the
// runner executes is what the job asked for.
#include "api/engine_settings.hpp"

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
