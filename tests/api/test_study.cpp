// Parameter studies (api/study.hpp): the grid and the explicit points expand
// to validated jobs, every bad document gets errors naming the point and the
// field, and the summary groups replicates with their spread.
#include "api/study.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace json = boost::json;
using namespace wiredem::api;

namespace {

json::value tiny()
{
    std::ifstream in(std::string(WIREDEM_SOURCE_DIR) + "/examples/tiny.json");
    std::stringstream s;
    s << in.rdbuf();
    return json::parse(s.str());
}

json::value study_with(json::object extra)
{
    json::value base = tiny();
    // A helix that fits the tiny column, for the points that lay one.
    base.at("specimen").at("wire").as_object()["helix_radius_m"] = 0.005;
    json::object d{{"name", "s"}, {"base", base}};
    for (auto& kv : extra) d[kv.key()] = kv.value();
    return d;
}

std::string all(const std::vector<FieldError>& errors)
{
    std::string s;
    for (const auto& e : errors) s += e.path + ": " + e.message + "\n";
    return s;
}

/// Whether some error has exactly `path` and a message containing `text`.
bool has_error(const std::vector<FieldError>& errors, const std::string& path, const std::string& text)
{
    for (const auto& e : errors)
        if (e.path == path && e.message.find(text) != std::string::npos) return true;
    return false;
}

} // namespace

TEST(Study, AGridExpandsToEveryCombinationTheLastPathFastest)
{
    const auto s = parse_study(study_with({{"vary", json::object{{"specimen.wire.pattern", json::array{"none", "helix"}},
                                                                  {"seed", json::array{1, 2, 3}}}}}));
    ASSERT_TRUE(s.ok()) << all(s.error());
    const Study& st = s.value();
    ASSERT_EQ(st.points.size(), 6u);
    EXPECT_EQ(st.paths, (std::vector<std::string>{"specimen.wire.pattern", "seed"}));
    EXPECT_EQ(st.points[0].label, "specimen.wire.pattern=\"none\" seed=1");
    EXPECT_EQ(st.points[4].label, "specimen.wire.pattern=\"helix\" seed=2");
    for (std::size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(st.points[i].spec.seed, i % 3 + 1);
        EXPECT_EQ(st.points[i].spec.specimen.wire.pattern, i < 3 ? WirePattern::none : WirePattern::helix);
        // Everything else is the base's.
        EXPECT_EQ(st.points[i].spec.specimen.grain_count, 150u);
        EXPECT_EQ(st.points[i].spec.name.rfind("s [" + std::to_string(i) + "] ", 0), 0u) << st.points[i].spec.name;
    }
}

TEST(Study, ExplicitPointsSetOnlyTheirOwnFields)
{
    const auto s = parse_study(study_with({{"points", json::array{json::object{{"seed", 7}},
                                                                   json::object{{"triaxial.plate_speed_m_per_s", 0.02}}}}}));
    ASSERT_TRUE(s.ok()) << all(s.error());
    ASSERT_EQ(s.value().points.size(), 2u);
    EXPECT_EQ(s.value().points[0].spec.seed, 7u);
    EXPECT_EQ(s.value().points[0].spec.triaxial.plate_speed_m_per_s(0), 0.04);
    EXPECT_EQ(s.value().points[1].spec.seed, 1u);
    EXPECT_EQ(s.value().points[1].spec.triaxial.plate_speed_m_per_s(0), 0.02);
}

TEST(Study, BadDocumentsNameThePointAndTheField)
{
    // A varied path that does not exist, a value of the wrong type, a value
    // out of range: each at its point, with the job parser's message.
    const auto s = parse_study(study_with({{"vary", json::object{{"specimen.wire.patern", json::array{"helix"}}}}}));
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(has_error(s.error(), "points[0] (specimen.wire.patern=\"helix\"): specimen.wire.patern", "unknown"))
        << all(s.error());
    const auto t = parse_study(study_with({{"vary", json::object{{"seed", json::array{1, "x", -3}}}}}));
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(t.error().size(), 2u) << all(t.error());
    EXPECT_EQ(t.error()[0].path, "points[1] (seed=\"x\"): seed") << all(t.error());
    EXPECT_EQ(t.error()[1].path, "points[2] (seed=-3): seed") << all(t.error());
    // One value, the list [-5]: pushed, since json::array{json::array{-5}}
    // is a copy of the inner array to clang (a one-element braced list of the
    // same type) and a list holding it to GCC.
    json::array one_list;
    one_list.push_back(json::array{-5});
    const auto u = parse_study(study_with({{"vary", json::object{{"triaxial.confining_pressures_pa", one_list}}}}));
    ASSERT_FALSE(u.ok());
    EXPECT_NE(all(u.error()).find("triaxial.confining_pressures_pa[0]"), std::string::npos) << all(u.error());
    // A path through a number.
    const auto v = parse_study(study_with({{"vary", json::object{{"seed.x", json::array{1}}}}}));
    ASSERT_FALSE(v.ok());
    EXPECT_TRUE(has_error(v.error(), "points[0] (seed.x=1): seed.x", "seed is not an object")) << all(v.error());
}

TEST(Study, AGridLargerThanTheLimitIsRefusedBeforeAnyJobIsBuilt)
{
    json::array many;
    for (int i = 0; i < 100; ++i) many.emplace_back(i + 1);
    const auto s = parse_study(study_with({{"vary", json::object{{"seed", many}, {"triaxial.plate_speed_m_per_s", json::array{0.01, 0.02, 0.03}}}}}), 256);
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(has_error(s.error(), "vary", "300 points (100 x 3), more than the limit of 256")) << all(s.error());
    // A product that overflows is still refused, not wrapped.
    json::object huge;
    for (int k = 0; k < 70; ++k) huge["seed" + std::string(k == 0 ? "" : ".x" + std::to_string(k))] = json::array{1, 2};
    const auto h = parse_study(study_with({{"vary", json::object{{"seed", many}, {"contact.friction_coefficient", many},
                                                                  {"specimen.grain_count", many}, {"specimen.grain_radius_m", many},
                                                                  {"triaxial.hold_time_s", many}, {"engine.density_scale", many},
                                                                  {"engine.wire_mass_scale", many}, {"comment", many},
                                                                  {"triaxial.target_axial_strain", many},
                                                                  {"specimen.membrane_radius_m", many}}}}));
    ASSERT_FALSE(h.ok());
    EXPECT_TRUE(has_error(h.error(), "vary", "too many points")) << all(h.error());
    const auto p = parse_study(study_with({{"points", json::array(300, json::object{{"seed", 1}})}}), 256);
    ASSERT_FALSE(p.ok());
    EXPECT_TRUE(has_error(p.error(), "points", "300 points, more than the limit of 256")) << all(p.error());
}

TEST(Study, MalformedStudiesAreRefusedWithTheirField)
{
    EXPECT_FALSE(parse_study(std::string_view("[1]")).ok());
    EXPECT_FALSE(parse_study(std::string_view("{")).ok());
    auto s = parse_study(json::parse(R"({"name": "s", "base": {}})"));
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(has_error(s.error(), "", "not neither")) << all(s.error());
    s = parse_study(study_with({{"vary", json::object{{"seed", json::array{1}}}}, {"points", json::array{json::object{}}}}));
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(has_error(s.error(), "", "not both")) << all(s.error());
    s = parse_study(study_with({{"vary", json::object{{"Seed!", json::array{1}}, {"name", json::array{"x"}}, {"seed", json::array{}}}},
        {"extra", 1}}));
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(has_error(s.error(), "vary.Seed!", "not a field path")) << all(s.error());
    EXPECT_TRUE(has_error(s.error(), "vary.name", "cannot be varied")) << all(s.error());
    EXPECT_TRUE(has_error(s.error(), "vary.seed", "non-empty list")) << all(s.error());
    EXPECT_TRUE(has_error(s.error(), "extra", "unknown field")) << all(s.error());
    s = parse_study(study_with({{"points", json::array{json::object{{"seed", 2}}, json::object{{"seed", 2}}}}}));
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(has_error(s.error(), "points[1]", "repeats points[0]")) << all(s.error());
    s = parse_study(json::parse(R"({"name": "", "base": 3, "vary": {"seed": [1]}})"));
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(has_error(s.error(), "name", "non-empty")) << all(s.error());
    EXPECT_TRUE(has_error(s.error(), "base", "object")) << all(s.error());
}

// A study's comment is bounded as a job's (api::max_comment_chars), and its
// name is one line of text as a job's: C1 controls included (U+009B is a
// terminal's CSI).
TEST(Study, ItsCommentIsBoundedAndItsNameOneLineAsAJobs)
{
    auto s = parse_study(study_with({{"comment", std::string(10'000, 'x')}, {"vary", json::object{{"seed", json::array{1}}}}}));
    EXPECT_TRUE(s.ok());
    s = parse_study(study_with({{"comment", std::string(10'001, 'x')}, {"vary", json::object{{"seed", json::array{1}}}}}));
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(has_error(s.error(), "comment", "is 10001 characters long; at most 10000")) << all(s.error());
    s = parse_study(study_with({{"name", "a\u009bb"}, {"vary", json::object{{"seed", json::array{1}}}}}));
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(has_error(s.error(), "name", "control character")) << all(s.error());
}

TEST(Study, TheSummaryGroupsReplicatesWithMeanSpreadAndCount)
{
    const auto s = parse_study(study_with({{"vary", json::object{{"specimen.wire.pattern", json::array{"none", "helix"}},
                                                                  {"seed", json::array{1, 2, 3}}}}}));
    ASSERT_TRUE(s.ok());
    const double phi[] = {30.0, 32.0, 34.0, 40.0, 0.0, 0.0};
    // The first point's fit has two caveats (summary.json mohr_coulomb.caveats), the others none.
    const auto caveats_of = [](int i) {
        json::array a;
        if (i == 0)
            for (const char* code : {"narrow_band", "negative_cohesion"}) a.push_back(json::object{{"code", code}, {"message", "m"}});
        return a;
    };
    std::vector<PointOutcome> outcomes;
    for (int i = 0; i < 6; ++i) {
        PointOutcome o;
        o.job_id = "job" + std::to_string(i);
        o.state = i < 4 ? "succeeded" : "failed";
        if (i < 4)
            o.summary = json::object{{"mohr_coulomb", json::object{{"friction_angle_deg", phi[i]}, {"cohesion_pa", 1000.0 * i},
                                                                    {"r_squared", 0.99}, {"caveats", caveats_of(i)}}},
                {"tests", json::array{json::object{{"confining_pressure_pa", 2e4}, {"peak_deviatoric_stress_pa", 5e4},
                    {"yield", json::object{{"deviatoric_stress_pa", 4e4}, {"shape", "peak"}}}}}},
                {"specimen", json::object{{"grain_volume_fraction", 0.6}}},
                {"wire", json::object{{"autocorrelation_lag_m", 0.04}, {"autocorrelation_prominent_lag_m", 0.1175}}}};
        else
            o.error = "boom, \"quoted\"";
        outcomes.push_back(o);
    }
    const json::object sum = study_summary(s.value(), outcomes);
    const json::array& groups = sum.at("groups").as_array();
    ASSERT_EQ(groups.size(), 2u);
    const json::object& none = groups[0].as_object();
    EXPECT_EQ(none.at("values"), (json::object{{"specimen.wire.pattern", "none"}}));
    EXPECT_EQ(none.at("succeeded").to_number<int>(), 3);
    EXPECT_DOUBLE_EQ(none.at("friction_angle_deg").at("mean").to_number<double>(), 32.0);
    EXPECT_DOUBLE_EQ(none.at("friction_angle_deg").at("sd").to_number<double>(), 2.0); // sample sd of 30, 32, 34
    EXPECT_EQ(none.at("friction_angle_deg").at("n").to_number<int>(), 3);
    const json::object& helix = groups[1].as_object();
    EXPECT_EQ(helix.at("succeeded").to_number<int>(), 1);
    EXPECT_DOUBLE_EQ(helix.at("friction_angle_deg").at("mean").to_number<double>(), 40.0);
    EXPECT_TRUE(helix.at("friction_angle_deg").at("sd").is_null()); // one value: no spread
    const json::object& row = sum.at("points").as_array()[0].as_object();
    EXPECT_EQ(row.at("yield_deviatoric_stress_pa"), (json::array{4e4}));
    EXPECT_EQ(row.at("job_id"), "job0");
    EXPECT_EQ(row.at("fit_caveats"), (json::array{"narrow_band", "negative_cohesion"}));
    EXPECT_EQ(sum.at("points").as_array()[1].at("fit_caveats"), json::array{});

    const std::string csv = study_summary_csv(sum);
    std::istringstream lines(csv);
    std::string header, first;
    std::getline(lines, header);
    std::getline(lines, first);
    EXPECT_EQ(header.rfind("index,specimen.wire.pattern,seed,state,job_id,friction_angle_deg", 0), 0u) << header;
    EXPECT_EQ(first, "0,none,1,succeeded,job0,30,0,0.99,20000,40000,peak,50000,0.6,,,,0.04,0.1175,narrow_band;negative_cohesion,");
    EXPECT_NE(csv.find("\"boom, \"\"quoted\"\"\""), std::string::npos) << csv; // a comma and quotes, escaped
}
