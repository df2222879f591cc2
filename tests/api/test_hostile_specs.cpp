// Specs the fuzz targets (tests/fuzz, docs/fuzzing.md) found mishandled: each
// test is a reduced input of a crash or property violation, and fails
// without its fix.
#include "api/derived.hpp"
#include "api/engine_settings.hpp"
#include "api/job_spec.hpp"
#include "specimen/box_preparation.hpp"

#include <gtest/gtest.h>

#include <time.h>

#include <cmath>
#include <limits>
#include <string>

using namespace wiredem::api;

namespace {

double thread_cpu_s()
{
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::string describe(const std::vector<FieldError>& errors)
{
    std::string s;
    for (const FieldError& e : errors) s += "  " + e.path + ": " + e.message + "\n";
    return s;
}

} // namespace

TEST(HostileSpecs, ValidationRunsNoCollisionFit)
{
    // Validation estimates the fill height and the wire's length from the
    // preparation spec, which used to resolve the restitution into a damping
    // time by bisecting on integrated collisions: 90-140 ms of CPU per spec in
    // Release (this spec: 174 ms), 1-3 s under the fuzz build's sanitizers.
    // Without the fit it validates in well under a millisecond in Release and
    // at most ~16 ms in the fuzz build (the slowest of its hostile inputs);
    // 50 ms leaves room for the sanitizer builds and stays below one fit.
    const std::string spec = R"({"specimen": {"wire": {"pattern": "spiral_helix"}},
                                 "contact": {"restitution": 0.3, "restitution_reference_speed_m_per_s": 0.05}})";
    const double t0 = thread_cpu_s();
    const auto parsed = parse_job_spec(std::string_view(spec));
    const double took_s = thread_cpu_s() - t0;
    ASSERT_TRUE(parsed.ok()) << describe(parsed.error());
    EXPECT_LT(took_s, 0.05);
    // The runner still gets the fitted damping time.
    EXPECT_GT(resolved_normal_damping_s(parsed.value()), 0.0);
}

TEST(HostileSpecs, ACuboidJobValidatesWithoutACollisionFit)
{
    // The door asks the box preparation's own rules (engine::
    // box_preparation_error) of a cuboid job; the box was built from
    // preparation_spec, whose restitution is fitted by integrated collisions.
    // fuzz_job_spec_values found it: examples/tiny-cuboid.json with a grain
    // modulus of 5e-324 took 1.4 s of CPU to validate in the fuzz build
    // (limit 1 s), the fit in subnormal numbers. The door now builds the box
    // from preparation_geometry (box_preparation_geometry), as the other
    // estimates do. The modulus's range now starts at 1e4 Pa, so the case
    // asks its floor, and 5e-324 is refused by its range.
    const std::string subnormal = R"({"specimen": {"wire": {"pattern": "none"}, "grain_count": 150,
                                              "grain": {"youngs_modulus_pa": 5e-324}},
                                 "triaxial": {"cell": "cuboid", "confining_pressures_pa": [1e4, 2e4]}})";
    const auto refused = parse_job_spec(std::string_view(subnormal));
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(describe(refused.error()).find("specimen.grain.youngs_modulus_pa: 5e-324 is out of range [10000, 1e+13]"),
        std::string::npos) << describe(refused.error());
    const std::string spec = R"({"specimen": {"wire": {"pattern": "none"}, "grain_count": 150,
                                              "grain": {"youngs_modulus_pa": 1e4}},
                                 "contact": {"restitution": 0.5},
                                 "triaxial": {"cell": "cuboid", "confining_pressures_pa": [1e4, 2e4]}})";
    const double t0 = thread_cpu_s();
    const auto parsed = parse_job_spec(std::string_view(spec));
    const double took_s = thread_cpu_s() - t0;
    EXPECT_LT(took_s, 0.05) << (parsed.ok() ? std::string("accepted") : describe(parsed.error()));
    // The same rules judge the box either way (only the damping differs).
    if (parsed.ok()) {
        const auto at_door = box_preparation_geometry(parsed.value());
        ASSERT_TRUE(at_door.ok()) << at_door.error();
        EXPECT_FALSE(wiredem::engine::box_preparation_error(at_door.value()).has_value());
    }
}

TEST(HostileSpecs, ABodyCountNoIntegerHoldsIsRefusedNotWrappedRound)
{
    // A membrane mesh of 1e-227 m has ~1e454 nodes: the count saturates at
    // the largest std::uint64_t, and grains + wire + membrane used to wrap
    // round to a few thousand, under engine.max_bodies (and every server's
    // limit).
    const auto parsed = parse_job_spec(std::string_view(R"({"specimen": {"membrane": {"mesh_size_m": 1.25e-227}}})"));
    ASSERT_FALSE(parsed.ok());
    bool at_max_bodies = false;
    for (const FieldError& e : parsed.error()) at_max_bodies = at_max_bodies || e.path == "engine.max_bodies";
    EXPECT_TRUE(at_max_bodies) << describe(parsed.error());

    BodyCounts n;
    n.grains = 8000;
    n.membrane_nodes = std::numeric_limits<std::uint64_t>::max();
    EXPECT_EQ(n.total(), std::numeric_limits<std::uint64_t>::max());
}

TEST(HostileSpecs, AJobOfMoreStepsThanAnyIntegerHoldsIsRefused)
{
    // δt = 1e-83 s is in (0, 1e-3] and below the stable limit, so the spec
    // was valid, and `wiredem run` cast ~1e82 expected steps to an integer
    // (undefined behaviour: engine::expected_triaxial_steps). Every job is
    // now held to api::max_steps_of_any_job, with the field named.
    const auto parsed = parse_job_spec(
        std::string_view(R"({"contact": {"normal_damping_s": 1e-6}, "engine": {"time_step_s": 1e-83}})"));
    ASSERT_FALSE(parsed.ok());
    ASSERT_EQ(parsed.error().size(), 1u) << describe(parsed.error());
    EXPECT_EQ(parsed.error()[0].path, "engine.time_step_s");
    EXPECT_NE(parsed.error()[0].message.find("no job may take more than 1e+15"), std::string::npos)
        << parsed.error()[0].message;

    // Just inside the ceiling stays valid: δt such that the work is below it.
    JobSpec ok;
    ok.contact.normal_damping = NormalDampingTime{1e-6};
    ok.engine.time_step_s = 1e-9;
    const WorkEstimate w = estimated_work(ok);
    ASSERT_LT(w.total_steps(), max_steps_of_any_job);
    EXPECT_TRUE(parse_job_spec(to_json(ok)).ok());
}
