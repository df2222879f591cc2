// specimen.grain_shape (every grain a rigid clump) at the door: read,
// written back (and left out of the written job when absent), refused with
// the field, the value and the rule; the preparation gets the clump at a
// volume-equivalent radius of 1.
#include "api/engine_settings.hpp"
#include "api/job_spec.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace wiredem::api {
namespace {
namespace json = boost::json;

std::string job_with(const std::string& shape)
{
    return R"({"specimen": {"wire": {"pattern": "none"}, "grain_shape": )" + shape + "}}";
}

std::string all(const std::vector<FieldError>& errors)
{
    std::string s;
    for (const FieldError& e : errors) s += "  " + e.path + ": " + e.message + "\n";
    return s;
}

void expect_refused(const std::string& shape, const std::string& path, const std::string& fragment)
{
    const auto r = parse_job_spec(json::parse(job_with(shape)));
    ASSERT_FALSE(r.ok()) << shape;
    const FieldError* found = nullptr;
    for (const FieldError& e : r.error())
        if (e.path == path) found = &e;
    ASSERT_NE(found, nullptr) << "no error at " << path << " for " << shape << "; got\n" << all(r.error());
    EXPECT_NE(found->message.find(fragment), std::string::npos) << found->message;
}

} // namespace

TEST(JobSpecGrainShape, ATemplateIsReadWrittenBackAndGivesTheClumpAtUnitEquivalentRadius)
{
    const auto r = parse_job_spec(json::parse(job_with(R"({"template": "crushed"})")));
    ASSERT_TRUE(r.ok()) << all(r.error());
    ASSERT_TRUE(r.value().specimen.grain_shape.has_value());
    EXPECT_EQ(r.value().specimen.grain_shape->template_name, "crushed");
    const json::value written = to_json(r.value());
    EXPECT_EQ(written.at("specimen").at("grain_shape"), json::parse(R"({"template": "crushed"})"));
    const auto again = parse_job_spec(written);
    ASSERT_TRUE(again.ok()) << all(again.error());
    EXPECT_EQ(again.value().specimen.grain_shape, r.value().specimen.grain_shape);
    const engine::ClumpBody body = grain_shape_body(*r.value().specimen.grain_shape);
    EXPECT_NEAR(body.volume_m3, 4.0 / 3.0 * std::numbers::pi, 1e-12);
    EXPECT_EQ(body.spheres.size(), 5u);
    const engine::PreparationSpec p = preparation_geometry(r.value());
    ASSERT_TRUE(p.grain_shape.has_value());
    EXPECT_NEAR(p.grain_shape->volume_m3, body.volume_m3, 1e-15);
}

TEST(JobSpecGrainShape, GivenSpheresAreReadAndWrittenBack)
{
    const auto r = parse_job_spec(json::parse(job_with(R"({"spheres": [[0, 0, 0, 1], [1.2, 0, 0, 0.8]]})")));
    ASSERT_TRUE(r.ok()) << all(r.error());
    const auto& g = *r.value().specimen.grain_shape;
    ASSERT_EQ(g.spheres.size(), 2u);
    EXPECT_EQ(g.spheres[1][0], 1.2);
    const auto again = parse_job_spec(to_json(r.value()));
    ASSERT_TRUE(again.ok()) << all(again.error());
    EXPECT_EQ(again.value().specimen.grain_shape, r.value().specimen.grain_shape);
}

TEST(JobSpecGrainShape, WithoutItTheWrittenJobHasNoSuchKey)
{
    const auto r = parse_job_spec(json::parse(R"({"specimen": {"wire": {"pattern": "none"}}})"));
    ASSERT_TRUE(r.ok()) << all(r.error());
    EXPECT_FALSE(r.value().specimen.grain_shape.has_value());
    EXPECT_FALSE(to_json(r.value()).at("specimen").as_object().contains("grain_shape"));
    const auto null_shape = parse_job_spec(json::parse(job_with("null")));
    ASSERT_TRUE(null_shape.ok()) << all(null_shape.error());
    EXPECT_FALSE(null_shape.value().specimen.grain_shape.has_value());
}

TEST(JobSpecGrainShape, BadShapesAreRefusedNamingTheFieldAndTheRule)
{
    expect_refused(R"({"template": "round"})", "specimen.grain_shape.template",
        R"("round" is not one of "elongated", "flat", "tetrahedral", "crushed")");
    expect_refused(R"({})", "specimen.grain_shape", R"(needs "template" or "spheres")");
    expect_refused(R"({"template": "flat", "spheres": [[0, 0, 0, 1], [1, 0, 0, 1]]})", "specimen.grain_shape",
        "give one");
    expect_refused(R"("crushed")", "specimen.grain_shape", "expected an object or null");
    expect_refused(R"({"spheres": [[0, 0, 0, 1]]})", "specimen.grain_shape.spheres", "a clump has 2 to 32");
    expect_refused(R"({"spheres": [[0, 0, 0, 1], [1, 0, 0]]})", "specimen.grain_shape.spheres[1]",
        "expected [x, y, z, radius]");
    expect_refused(R"({"spheres": [[0, 0, 0, 1], [1, 0, 0, 0]]})", "specimen.grain_shape.spheres[1][3]", "");
    expect_refused(R"({"spheres": [[0, 0, 0, 1], [1, 0, 0, 0.05]]})", "specimen.grain_shape.spheres[1][3]",
        "below 0.1 × the largest radius 1");
    expect_refused(R"({"spheres": [[0, 0, 0, 1], [1.5, 0, 0, 1], [5, 0, 0, 1]]})", "specimen.grain_shape.spheres[2]",
        "touches no sphere connected to the first");
    expect_refused(R"({"template": "flat", "scale": 2})", "specimen.grain_shape.scale", "unknown key");
}

TEST(JobSpecGrainShape, TheColumnWidthCheckTakesTheClumpsExtent)
{
    // r = 1.9 mm in R = 8 mm passes as spheres (over 4 diameters wide); a
    // crushed clump of that volume reaches 1.43 r (largest_grain_radius_m),
    // and is refused.
    const std::string sized = R"({"specimen": {"wire": {"pattern": "none"}, "membrane_radius_m": 0.008, "grain_radius_m": 0.0019)";
    const auto spheres = parse_job_spec(json::parse(sized + "}}"));
    const auto clumps = parse_job_spec(json::parse(sized + R"(, "grain_shape": {"template": "crushed"}}})"));
    std::string spheres_errors = spheres.ok() ? "" : all(spheres.error());
    EXPECT_EQ(spheres_errors.find("too big for the membrane"), std::string::npos) << spheres_errors;
    ASSERT_FALSE(clumps.ok());
    EXPECT_NE(all(clumps.error()).find("too big for the membrane"), std::string::npos) << all(clumps.error());
    // And says why a radius below membrane_radius_m / 4 is refused: the clump's reach.
    EXPECT_NE(all(clumps.error()).find("the clump of specimen.grain_shape reaches 1.43 × the grain's radius from its centre, "
                                       "so the largest grain spans 0.00542"),
        std::string::npos)
        << all(clumps.error());
    EXPECT_EQ(spheres_errors.find("clump"), std::string::npos) << spheres_errors;
}

} // namespace wiredem::api
