// specimen.grain_sizes (a grain-size curve) at the door: read, written back,
// and refused with the field, the value and the rule when it cannot be
// drawn from or does not fit the column; the estimates validation makes
// (the stable time step, the fill) take the curve's sizes.
#include "api/derived.hpp"
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

/// A job without wire (the wire's checks are not what is tested) with `curve`.
std::string job_with(const std::string& curve, const std::string& extra = "")
{
    return R"({"specimen": {"wire": {"pattern": "none"}, "grain_sizes": )" + curve + extra + "}}";
}

const std::string gravel = R"({"basis": "mass", "diameters_m": [1.6e-3, 2.4e-3, 3.2e-3], "fraction_passing": [0, 0.4, 1]})";

/// The error at `path`, or nullptr.
const FieldError* error_at(const std::vector<FieldError>& errors, const std::string& path)
{
    for (const FieldError& e : errors)
        if (e.path == path) return &e;
    return nullptr;
}

std::string all(const std::vector<FieldError>& errors)
{
    std::string s;
    for (const FieldError& e : errors) s += "  " + e.path + ": " + e.message + "\n";
    return s;
}

void expect_refused(const std::string& doc, const std::string& path, const std::string& fragment)
{
    const auto r = parse_job_spec(json::parse(doc));
    ASSERT_FALSE(r.ok()) << doc;
    const FieldError* e = error_at(r.error(), path);
    ASSERT_NE(e, nullptr) << "no error at " << path << " for " << doc << "; got\n" << all(r.error());
    EXPECT_NE(e->message.find(fragment), std::string::npos) << e->message;
}

} // namespace

TEST(JobSpecGrainSizes, ACurveIsReadAndWrittenBack)
{
    const auto r = parse_job_spec(json::parse(job_with(gravel)));
    ASSERT_TRUE(r.ok()) << all(r.error());
    const JobSpec& s = r.value();
    ASSERT_TRUE(s.specimen.grain_sizes.has_value());
    EXPECT_EQ(s.specimen.grain_sizes->basis, GrainSizeBasis::mass);
    EXPECT_EQ(s.specimen.grain_sizes->diameters_m, (std::vector<double>{1.6e-3, 2.4e-3, 3.2e-3}));
    EXPECT_EQ(s.specimen.grain_sizes->fraction_passing, (std::vector<double>{0.0, 0.4, 1.0}));
    // Written without the radius and spread it replaces, and read back the same.
    const json::value j = to_json(s);
    EXPECT_FALSE(j.at("specimen").as_object().contains("grain_radius_m"));
    EXPECT_FALSE(j.at("specimen").as_object().contains("grain_radius_spread"));
    const auto again = parse_job_spec(j);
    ASSERT_TRUE(again.ok()) << all(again.error());
    EXPECT_EQ(again.value(), s);
    // A number curve too; null is the spread (the default).
    const auto number = parse_job_spec(json::parse(job_with(
        R"({"basis": "number", "diameters_m": [2e-3, 3e-3], "fraction_passing": [0, 1]})")));
    ASSERT_TRUE(number.ok()) << all(number.error());
    EXPECT_EQ(number.value().specimen.grain_sizes->basis, GrainSizeBasis::number);
    EXPECT_EQ(parse_job_spec(to_json(number.value())).value(), number.value());
    const auto none = parse_job_spec(json::parse(job_with("null")));
    ASSERT_TRUE(none.ok());
    EXPECT_FALSE(none.value().specimen.grain_sizes.has_value());
    EXPECT_TRUE(to_json(JobSpec{}).at("specimen").at("grain_sizes").is_null());
}

TEST(JobSpecGrainSizes, RefusesACurveThatCannotBeDrawnFrom)
{
    expect_refused(job_with(R"({"diameters_m": [2e-3, 1e-3], "fraction_passing": [0, 1]})"),
        "specimen.grain_sizes.diameters_m[1]", "is not greater than the previous entry");
    expect_refused(job_with(R"({"diameters_m": [1e-3, 1.0005e-3], "fraction_passing": [0, 1]})"),
        "specimen.grain_sizes.diameters_m[1]", "is within 0.1 % of the previous size");
    expect_refused(job_with(R"({"diameters_m": [1e-5, 1e-3], "fraction_passing": [0, 1]})"),
        "specimen.grain_sizes.diameters_m[0]", "1e-05 is out of range [2e-05, 0.2]");
    expect_refused(job_with(R"({"diameters_m": [1e-3, 0.3], "fraction_passing": [0, 1]})"),
        "specimen.grain_sizes.diameters_m[1]", "0.3 is out of range [2e-05, 0.2]");
    expect_refused(job_with(R"({"diameters_m": [1e-3], "fraction_passing": [1]})"),
        "specimen.grain_sizes.diameters_m", "has 1 entries; allowed 2 to 64");
    expect_refused(job_with(R"({"diameters_m": [1e-3, 2e-3, 3e-3], "fraction_passing": [0, 0.6, 0.5]})"),
        "specimen.grain_sizes.fraction_passing[2]", "0.5 is less than the previous entry 0.6");
    expect_refused(job_with(R"({"diameters_m": [1e-3, 2e-3], "fraction_passing": [0.1, 1]})"),
        "specimen.grain_sizes.fraction_passing[0]", "0.1 is not 0");
    expect_refused(job_with(R"({"diameters_m": [1e-3, 2e-3], "fraction_passing": [0, 0.9]})"),
        "specimen.grain_sizes.fraction_passing[1]", "0.9 is not 1");
    expect_refused(job_with(R"({"diameters_m": [1e-3, 2e-3], "fraction_passing": [0, 1.5]})"),
        "specimen.grain_sizes.fraction_passing[1]", "1.5 is out of range [0, 1]");
    expect_refused(job_with(R"({"diameters_m": [1e-3, 2e-3, 3e-3], "fraction_passing": [0, 1]})"),
        "specimen.grain_sizes.fraction_passing", "has 2 entries for 3 diameters");
    expect_refused(job_with(R"({"diameters_m": [1e-3, 2e-3]})"), "specimen.grain_sizes.fraction_passing", "is missing");
    expect_refused(job_with(R"({"fraction_passing": [0, 1]})"), "specimen.grain_sizes.diameters_m", "is missing");
    expect_refused(job_with(R"({"basis": "volume", "diameters_m": [1e-3, 2e-3], "fraction_passing": [0, 1]})"),
        "specimen.grain_sizes.basis", "\"volume\" is not one of \"mass\", \"number\"");
    expect_refused(job_with(R"({"diameters_m": [1e-3, 2e-3], "fraction_passing": [0, 1], "sizes": 1})"),
        "specimen.grain_sizes.sizes", "unknown key");
    expect_refused(job_with("[1e-3, 2e-3]"), "specimen.grain_sizes", "expected an object or null, got an array");
}

TEST(JobSpecGrainSizes, RefusesARadiusOrSpreadBesideACurve)
{
    expect_refused(job_with(gravel, R"(, "grain_radius_m": 1e-3)"), "specimen.grain_radius_m",
        "is given with specimen.grain_sizes");
    expect_refused(job_with(gravel, R"(, "grain_radius_spread": 0.1)"), "specimen.grain_radius_spread",
        "is given with specimen.grain_sizes");
}

TEST(JobSpecGrainSizes, TheLargestGrainMustFitTheColumnAndTheSmallestTheMesh)
{
    // R = 20 mm holds 4 diameters of at most 10 mm.
    expect_refused(job_with(R"({"diameters_m": [2e-3, 12e-3], "fraction_passing": [0, 1]})"),
        "specimen.grain_sizes.diameters_m", "the largest diameter 0.012 is too big for the membrane");
    // l_m = 1.25 mm lets a grain of radius below l_m/√3 − r_m = 0.22 mm through.
    expect_refused(job_with(R"({"diameters_m": [0.4e-3, 2e-3], "fraction_passing": [0, 1]})"),
        "specimen.membrane.mesh_size_m", "the smallest grain (radius 0.0002)");
}

TEST(JobSpecGrainSizes, TheTimeStepTakesTheSmallestGrainAndTheFillTheMeanVolume)
{
    const auto curve = parse_job_spec(json::parse(job_with(
        R"({"basis": "number", "diameters_m": [1.6e-3, 3.2e-3], "fraction_passing": [0, 1]})")));
    ASSERT_TRUE(curve.ok()) << all(curve.error());
    // The same grains all of the smallest size: the same stable step.
    JobSpec smallest = curve.value();
    smallest.specimen.grain_sizes.reset();
    smallest.specimen.grain_radius_m = 0.8e-3;
    EXPECT_EQ(stable_time_step(curve.value()).critical_s, stable_time_step(smallest).critical_s);
    // The fill: N (π/6) E[D³] with E[D³] = (b³ − a³)/(3 ln(b/a)) for a
    // number curve of one interval, over 0.58 π R².
    const double a = 1.6e-3, b = 3.2e-3, R = 0.02;
    const double mean_cube = (b * b * b - a * a * a) / (3.0 * std::log(b / a));
    const double fill = 8000.0 * std::numbers::pi / 6.0 * mean_cube / (0.58 * std::numbers::pi * R * R);
    EXPECT_NEAR(engine::estimated_fill_height_m(preparation_geometry(curve.value())), fill, 1e-12 * fill);
}

} // namespace wiredem::api
