// specimen.grain_preset (a named grain, api/grain_presets.hpp) at the door:
// the reader fills the fields the preset names, its sieve curve scaled to
// D50 = 2 grain_radius_m; the writer writes the name instead of them, so a
// round trip gives the same spec; a field the preset sets, given beside it,
// is refused naming both; a job without a preset writes no such key.
#include "api/engine_settings.hpp"
#include "api/job_spec.hpp"
#include "specimen/grain_sizes.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace wiredem::api {
namespace {
namespace json = boost::json;

std::string all(const std::vector<FieldError>& errors)
{
    std::string s;
    for (const FieldError& e : errors) s += "  " + e.path + ": " + e.message + "\n";
    return s;
}

/// A small column (20 mm, 2 mm grains) with the gravel preset and `extra`
/// spliced into specimen, and `contact` as the contact object.
std::string gravel_job(const std::string& extra = "", const std::string& contact = "{}")
{
    return R"({"specimen": {"membrane_radius_m": 0.02, "grain_count": 300, "grain_radius_m": 0.001,
               "wire": {"pattern": "none"}, "grain_preset": "gravel")"
        + extra + R"(}, "contact": )" + contact + "}";
}

const FieldError* error_at(const std::vector<FieldError>& errors, const std::string& path)
{
    for (const FieldError& e : errors)
        if (e.path == path) return &e;
    return nullptr;
}

} // namespace

TEST(JobSpecGrainPreset, GravelSetsTheCrushedClumpItsCurveAtTheColumnsScaleAndItsFriction)
{
    const auto r = parse_job_spec(json::parse(gravel_job()));
    ASSERT_TRUE(r.ok()) << all(r.error());
    const JobSpec& spec = r.value();
    EXPECT_EQ(spec.specimen.grain_preset, GrainPreset::gravel);
    ASSERT_TRUE(spec.specimen.grain_shape.has_value());
    EXPECT_EQ(spec.specimen.grain_shape->template_name, gravel_preset.clump_template);
    ASSERT_TRUE(spec.specimen.grain_sizes.has_value());
    const GrainSizesSpec& g = *spec.specimen.grain_sizes;
    EXPECT_EQ(g.basis, GrainSizeBasis::mass);
    ASSERT_EQ(g.diameters_m.size(), gravel_preset.sieve_mm.size());
    // The lab's curve scaled as a whole: the same ratios, the same fractions.
    for (std::size_t k = 0; k < g.diameters_m.size(); ++k) {
        EXPECT_NEAR(g.diameters_m[k] / g.diameters_m[0], gravel_preset.sieve_mm[k] / gravel_preset.sieve_mm[0], 1e-12);
        EXPECT_EQ(g.fraction_passing[k], gravel_preset.fraction_passing[k]);
    }
    // Its D50 is the column's grain diameter 2 r_p, and reference_grain_radius_m reads r_p back.
    const engine::GrainSizeDistribution d(sieve_curve(g));
    EXPECT_NEAR(d.diameter_at_mass_fraction(0.5), 2e-3, 1e-15);
    EXPECT_NEAR(reference_grain_radius_m(spec.specimen), 1e-3, 1e-15);
    // An 8/32 gravel: D60/D10 = 2.0 (log-linear between 8 and 11.2 mm, 16 and 22.4 mm).
    EXPECT_NEAR(d.diameter_at_mass_fraction(0.6) / d.diameter_at_mass_fraction(0.1), 2.0, 1e-12);
    EXPECT_EQ(spec.contact.tangential.friction_coeff, gravel_preset.friction_coeff);
    EXPECT_EQ(spec.contact.rolling.friction_coeff, gravel_preset.rolling_friction_coeff);
    EXPECT_EQ(spec.contact.rolling.damping_ratio, gravel_preset.rolling_damping_ratio);
}

TEST(JobSpecGrainPreset, IsWrittenAsItsNameAndReadsBackTheSameSpec)
{
    const auto r = parse_job_spec(json::parse(gravel_job()));
    ASSERT_TRUE(r.ok()) << all(r.error());
    const json::value written = to_json(r.value());
    const json::object& specimen = written.at("specimen").as_object();
    EXPECT_EQ(specimen.at("grain_preset"), json::value("gravel"));
    EXPECT_EQ(specimen.at("grain_radius_m"), json::value(0.001));
    for (const char* key : {"grain_sizes", "grain_shape", "grain_radius_spread"}) EXPECT_FALSE(specimen.contains(key)) << key;
    const json::object& contact = written.at("contact").as_object();
    for (const char* key : {"friction_coeff", "rolling_friction_coeff", "rolling_damping_ratio"})
        EXPECT_FALSE(contact.contains(key)) << key;
    EXPECT_TRUE(contact.contains("tangential_stiffness_per_m"));  // the fields the preset leaves alone stay
    const auto again = parse_job_spec(written);
    ASSERT_TRUE(again.ok()) << all(again.error());
    EXPECT_EQ(again.value(), r.value());
}

TEST(JobSpecGrainPreset, AJobWithoutOneWritesNoPresetAndKeepsItsFields)
{
    const auto r = parse_job_spec(json::parse(R"({"specimen": {"grain_shape": {"template": "crushed"}, "wire": {"pattern": "none"}},
                                                  "contact": {"friction_coeff": 0.6}})"));
    ASSERT_TRUE(r.ok()) << all(r.error());
    EXPECT_EQ(r.value().specimen.grain_preset, GrainPreset::none);
    const json::value written = to_json(r.value());
    EXPECT_FALSE(written.at("specimen").as_object().contains("grain_preset"));
    EXPECT_EQ(written.at("contact").at("friction_coeff"), json::value(0.6));
    EXPECT_TRUE(written.at("specimen").as_object().contains("grain_shape"));
}

TEST(JobSpecGrainPreset, RefusesEachFieldItSetsGivenBesideItNamingBoth)
{
    const std::vector<std::pair<std::string, std::string>> cases{
        {gravel_job(R"(, "grain_shape": {"template": "flat"})"), "specimen.grain_shape"},
        {gravel_job(R"(, "grain_sizes": {"diameters_m": [0.001, 0.002], "fraction_passing": [0, 1]})"), "specimen.grain_sizes"},
        {gravel_job(R"(, "grain_radius_spread": 0.1)"), "specimen.grain_radius_spread"},
        {gravel_job("", R"({"friction_coeff": 0.3})"), "contact.friction_coeff"},
        {gravel_job("", R"({"rolling_friction_coeff": 0.2})"), "contact.rolling_friction_coeff"},
        {gravel_job("", R"({"rolling_damping_ratio": 0.1})"), "contact.rolling_damping_ratio"},
    };
    for (const auto& [text, path] : cases) {
        const auto r = parse_job_spec(json::parse(text));
        ASSERT_FALSE(r.ok()) << path;
        const FieldError* e = error_at(r.error(), path);
        ASSERT_NE(e, nullptr) << "no error at " << path << "; got\n" << all(r.error());
        EXPECT_NE(e->message.find("specimen.grain_preset \"gravel\""), std::string::npos) << e->message;
    }
}

TEST(JobSpecGrainPreset, RefusesAnUnknownNameAndAScaleTheColumnCannotHoldAtTheFieldsThatSetThem)
{
    const auto unknown = parse_job_spec(json::parse(
        R"({"specimen": {"wire": {"pattern": "none"}, "grain_preset": "sand"}})"));
    ASSERT_FALSE(unknown.ok());
    const FieldError* e = error_at(unknown.error(), "specimen.grain_preset");
    ASSERT_NE(e, nullptr) << all(unknown.error());
    EXPECT_NE(e->message.find("\"sand\" is not one of \"none\", \"gravel\""), std::string::npos) << e->message;

    // 4 mm grains (D_max 7 mm, a clump 1.43 × that) in a 20 mm column: fewer than 4 across.
    const auto big = parse_job_spec(json::parse(
        R"({"specimen": {"membrane_radius_m": 0.02, "grain_radius_m": 0.002, "wire": {"pattern": "none"}, "grain_preset": "gravel"}})"));
    ASSERT_FALSE(big.ok());
    e = error_at(big.error(), "specimen.grain_radius_m");
    ASSERT_NE(e, nullptr) << all(big.error());
    EXPECT_NE(e->message.find("with specimen.grain_preset \"gravel\", the largest diameter"), std::string::npos) << e->message;
}

// The calibration's record (docs/model.md, "A calibrated gravel"): the heap
// job that names the preset is the calibration run of the preset's own μ_r,
// field for field, so the run recorded for that μ_r is the preset's.
TEST(JobSpecGrainPreset, ThePresetsHeapJobIsTheCalibrationRunOfItsRollingFriction)
{
    const auto read = [](const std::string& name) {
        std::ifstream in(std::string(WIREDEM_SOURCE_DIR) + "/docs/calibration/gravel/" + name);
        std::stringstream text;
        text << in.rdbuf();
        return parse_job_spec(text.str());
    };
    std::ostringstream mu_r;
    mu_r << gravel_preset.rolling_friction_coeff;
    const auto preset = read("repose-preset.json");
    const auto run = read("repose-mu_r-" + mu_r.str() + ".json");
    ASSERT_TRUE(preset.ok()) << all(preset.error());
    ASSERT_TRUE(run.ok()) << "no calibration run at the preset's mu_r = " << mu_r.str() << ": " << all(run.error());
    JobSpec a = preset.value(), b = run.value();
    a.name = b.name;
    a.comment = b.comment;
    a.specimen.grain_preset = GrainPreset::none;
    a.specimen.grain_radius_m = b.specimen.grain_radius_m;  // the curve sets the sizes: the scale is in it
    ASSERT_TRUE(a.specimen.grain_sizes && b.specimen.grain_sizes);
    // The script writes the scaled sizes rounded to 1 nm.
    for (std::size_t k = 0; k < a.specimen.grain_sizes->diameters_m.size(); ++k)
        EXPECT_NEAR(a.specimen.grain_sizes->diameters_m[k], b.specimen.grain_sizes->diameters_m[k], 1e-9);
    a.specimen.grain_sizes = b.specimen.grain_sizes;
    EXPECT_EQ(a, b);
}

} // namespace wiredem::api
