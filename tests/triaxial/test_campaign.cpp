// `wiredem run` end to end: the real binary on examples/tiny.json (a few
// seconds in Release), then its summary.json and result.h5 are checked; and
// SIGTERM stops a run within a second with exit code 143.
//
// WIREDEM_BIN comes from tests/triaxial/CMakeLists.txt, WIREDEM_SOURCE_DIR from
// wiredem_test_support (tests/CMakeLists.txt).
#include "io/hdf5.hpp"
#include "source_tree.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include <csignal>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace fs = std::filesystem;
namespace json = boost::json;
using wiredem::engine::io::File;
using wiredem::test_support::read_text;
using wiredem::test_support::source;

namespace {

fs::path fresh_dir(const std::string& name)
{
    const fs::path dir = fs::temp_directory_path() / ("wiredem_campaign_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

/// Runs `wiredem run JOB -o OUT --threads 2 --progress json`; returns the wait status.
int run_binary(const fs::path& job, const fs::path& out, const fs::path& log, pid_t* pid_out = nullptr, bool wait = true)
{
    const std::string bin = WIREDEM_BIN, job_s = job.string(), out_s = out.string(), log_s = log.string();
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, (log_s + ".stdout").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, (log_s + ".stderr").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const char* argv[] = {bin.c_str(), "run", job_s.c_str(), "-o", out_s.c_str(), "--threads", "2", "--progress", "json",
        nullptr};
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, bin.c_str(), &fa, nullptr, const_cast<char* const*>(argv), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) return -1;
    if (pid_out) *pid_out = pid;
    if (!wait) return 0;
    int status = 0;
    waitpid(pid, &status, 0);
    return status;
}

const json::value& at(const json::value& v, std::initializer_list<const char*> path)
{
    const json::value* p = &v;
    for (const char* k : path) p = &p->as_object().at(k);
    return *p;
}

} // namespace

TEST(Campaign, TinyJobWritesASaneSummaryAndResultFile)
{
    const fs::path dir = fresh_dir("tiny"), out = dir / "out";
    const int status = run_binary(source("examples/tiny.json"), out, dir / "log");
    const std::string err = read_text(dir / "log.stderr");
    ASSERT_TRUE(WIFEXITED(status)) << err;
    ASSERT_EQ(WEXITSTATUS(status), 0) << err;

    // Progress: JSON lines with the four fields, never going back, ending at 1.
    std::istringstream lines(read_text(dir / "log.stdout"));
    std::string line, last;
    int count = 0;
    double previous = 0.0;
    while (std::getline(lines, line)) {
        const json::value p = json::parse(line);
        ASSERT_TRUE(p.as_object().contains("stage")) << line;
        const double f = p.at("progress").to_number<double>();
        EXPECT_GE(f, previous) << line;
        EXPECT_LE(f, 1.0);
        previous = f;
        EXPECT_TRUE(p.at("eta_s").is_null() || p.at("eta_s").is_number()) << line;
        EXPECT_TRUE(p.at("message").is_string()) << line;
        last = line, ++count;
    }
    EXPECT_GT(count, 2);
    EXPECT_EQ(json::parse(last).at("progress").to_number<double>(), 1.0);

    // summary.json: the fields of the contract, physically sane.
    ASSERT_TRUE(fs::exists(out / "summary.json"));
    EXPECT_FALSE(fs::exists(out / "summary.json.partial"));
    const json::value s = json::parse(read_text(out / "summary.json"));
    const json::array& tests = s.at("tests").as_array();
    ASSERT_EQ(tests.size(), 2u);
    std::ptrdiff_t unconsolidated = 0;
    for (const json::value& t : tests) {
        const double s1 = t.at("sigma1_pa").to_number<double>(), s3 = t.at("sigma3_effective_pa").to_number<double>();
        EXPECT_GT(s3, 0.0) << json::serialize(t);
        EXPECT_GT(s1, s3) << json::serialize(t);
        EXPECT_GT(t.at("peak_deviatoric_stress_pa").to_number<double>(), 0.0);
        EXPECT_GT(t.at("peak_axial_strain").to_number<double>(), 0.0);
        EXPECT_LE(t.at("peak_axial_strain").to_number<double>(), 0.081);
        EXPECT_TRUE(t.at("quasi_static").is_bool());
        EXPECT_TRUE(t.at("confining_pressure_pa").is_number());
        // The yield state: a Mohr circle in compression whose top lies on the
        // stress ratio it was read at, and what kind of maximum it was.
        const json::value& y = t.at("yield");
        const double y1 = y.at("sigma1_pa").to_number<double>(), y3 = y.at("sigma3_effective_pa").to_number<double>();
        EXPECT_GT(y3, 0.0) << json::serialize(y);
        EXPECT_GT(y1, y3) << json::serialize(y);
        EXPECT_NEAR(y.at("stress_ratio").to_number<double>(), (y1 - y3) / (y1 + y3), 1e-12);
        for (const json::value* shape : {&y.at("shape"), &t.at("max_q_shape")})
            EXPECT_TRUE(*shape == "peak" || *shape == "plateau" || *shape == "rising") << json::serialize(*shape);
        EXPECT_GT(t.at("hold_time_s").to_number<double>(), 0.0);
        EXPECT_EQ(t.at("consolidation"), "effective"); // tiny.json leaves triaxial.consolidation at its default
        // What it was brought to, σ₃,eff: the membrane's own contacts, not σ₃;
        // and the verdict is the warning's.
        const double target = t.at("consolidation_target_pa").to_number<double>();
        EXPECT_GT(target, 0.0);
        EXPECT_NE(target, t.at("confining_pressure_pa").to_number<double>());
        unconsolidated += t.at("consolidated").as_bool() ? 0 : 1;
    }
    // One "had not consolidated" warning for each test that was not.
    EXPECT_EQ(std::ranges::count_if(s.at("warnings").as_array(), [](const json::value& w) {
        return std::string_view(w.as_string()).find("had not consolidated") != std::string_view::npos;
    }), unconsolidated);
    for (const char* fit : {"mohr_coulomb", "mohr_coulomb_max_q"}) {
        for (const char* k : {"friction_angle_deg", "cohesion_pa", "r_squared", "paper_top_line_angle_deg", "states"})
            EXPECT_TRUE(at(s, {fit}).as_object().contains(k)) << fit << "." << k;
        EXPECT_TRUE(at(s, {fit, "friction_angle_deg"}).is_number()) << fit;
    }
    // Two tests: the tangent fit through their two circle tops (p, t) is the
    // line through both, sin φ = Δt/Δp and c cos φ = t − p sin φ, whatever
    // the circles. (tiny.json loads far too fast to be quasi-static: both
    // maxima of q and of the stress ratio come in the first 0.3 % of strain,
    // where the plate strikes the column, at q ≈ 70–75 kPa for either σ₃, so
    // the sign of φ here is the impact's noise, not a strength: measured
    // +1.2° consolidated to the cell pressure and −5.2° to σ₃,eff.)
    {
        std::vector<std::pair<double, double>> tops; // (p, t)
        for (const json::value& t : tests) {
            const double s1 = t.at("sigma1_pa").to_number<double>(), s3 = t.at("sigma3_effective_pa").to_number<double>();
            tops.emplace_back(0.5 * (s1 + s3), 0.5 * (s1 - s3));
        }
        const double sin_phi = (tops[1].second - tops[0].second) / (tops[1].first - tops[0].first);
        const double phi = std::asin(sin_phi);
        const double c = (tops[0].second - tops[0].first * sin_phi) / std::cos(phi);
        EXPECT_NEAR(at(s, {"mohr_coulomb_max_q", "friction_angle_deg"}).to_number<double>(), phi * 180.0 / std::numbers::pi, 1e-9);
        EXPECT_NEAR(at(s, {"mohr_coulomb_max_q", "cohesion_pa"}).to_number<double>(), c, 1e-9 * std::abs(c) + 1e-6);
        // ... and so it has no R² and says why, in the fit and in the warnings.
        EXPECT_TRUE(at(s, {"mohr_coulomb_max_q", "r_squared"}).is_null());
        for (const char* fit : {"mohr_coulomb", "mohr_coulomb_max_q"}) {
            EXPECT_EQ(at(s, {fit, "caveats"}).as_array().at(0).at("code"), "two_pressures") << fit;
            EXPECT_TRUE(at(s, {fit, "cohesionless", "r_squared"}).is_number()) << fit;
            EXPECT_GE(at(s, {fit, "nonnegative", "cohesion_pa"}).to_number<double>(), 0.0) << fit;
            EXPECT_GE(at(s, {fit, "nonnegative", "friction_angle_deg"}).to_number<double>(), 0.0) << fit;
            EXPECT_EQ(at(s, {fit, "cohesionless", "cohesion_pa"}).to_number<double>(), 0.0) << fit;
        }
        EXPECT_EQ(std::ranges::count_if(s.at("warnings").as_array(), [](const json::value& w) {
            return std::string_view(w.as_string()).find("two pressures: a line passes through any two circle tops")
                != std::string_view::npos;
        }), 2);
    }
    EXPECT_TRUE(s.at("definitions").as_object().contains("yield"));
    for (const char* k : {"grain_volume_fraction", "wire_volume_fraction", "sample_volume_m3", "grains", "wire_nodes",
             "wire_length_m", "pile_height_m"})
        EXPECT_TRUE(at(s, {"specimen"}).as_object().contains(k)) << k;
    EXPECT_EQ(at(s, {"specimen", "grains"}).to_number<std::int64_t>(), 150);
    const double phi = at(s, {"specimen", "grain_volume_fraction"}).to_number<double>();
    EXPECT_GT(phi, 0.2);
    EXPECT_LT(phi, 0.65);
    EXPECT_TRUE(at(s, {"wire"}).as_object().contains("autocorrelation_lag_m"));
    EXPECT_TRUE(s.at("warnings").is_array());
    EXPECT_GT(at(s, {"engine", "time_step_s"}).to_number<double>(), 0.0);
    EXPECT_GT(at(s, {"engine", "steps"}).to_number<std::int64_t>(), 0);
    EXPECT_GT(at(s, {"engine", "body_steps_per_second"}).to_number<double>(), 0.0);
    EXPECT_EQ(at(s, {"engine", "threads"}).to_number<std::int64_t>(), 2);

    // result.h5: format, job spec, specimen and one group per test.
    ASSERT_TRUE(fs::exists(out / "result.h5"));
    EXPECT_FALSE(fs::exists(out / "result.h5.tmp"));
    const File f = File::open_read_only(out / "result.h5");
    const auto root = f.root();
    EXPECT_EQ(root.read_string_attribute("format"), "wiredem-result-1");
    const json::value spec = json::parse(root.open_dataset("job_spec").read_string());
    EXPECT_EQ(at(spec, {"specimen", "grain_count"}).to_number<std::int64_t>(), 150);
    const auto specimen = root.open_group("specimen");
    EXPECT_EQ(specimen.read_int_attribute("grains"), 150);
    EXPECT_EQ(specimen.open_dataset("grain_position_m").shape(), (std::vector<std::size_t>{150, 3}));
    EXPECT_EQ(specimen.open_dataset("grain_radius_m").read_string_attribute("units"), "m");
    for (const char* name : {"sigma3_10000", "sigma3_20000"}) {
        ASSERT_TRUE(root.exists(std::string("tests/") + name)) << name;
        const auto t = root.open_group(std::string("tests/") + name);
        const auto q = t.open_dataset("deviatoric_stress_pa");
        EXPECT_EQ(q.read_string_attribute("units"), "Pa");
        const std::size_t n = q.shape().at(0);
        EXPECT_GT(n, 10u);
        EXPECT_EQ(t.open_dataset("axial_strain").shape().at(0), n);
        EXPECT_EQ(t.open_dataset("time_s").read_string_attribute("units"), "s");
        const auto snaps = t.open_group("snapshots");
        ASSERT_GE(snaps.child_names().size(), 2u);
        EXPECT_EQ(snaps.open_group("snapshot_0").open_dataset("grain_position_m").shape(),
            (std::vector<std::size_t>{150, 3}));
    }
    fs::remove_all(dir);
}

// The rigid-wall cell as a job (triaxial.cell = cuboid, examples/tiny-cuboid.json):
// the box preparation and the cuboid tests through the same stages and files.
TEST(Campaign, ACuboidCellJobWritesItsSummaryAndResultFile)
{
    const fs::path dir = fresh_dir("cuboid"), out = dir / "out";
    const int status = run_binary(source("examples/tiny-cuboid.json"), out, dir / "log");
    const std::string err = read_text(dir / "log.stderr");
    ASSERT_TRUE(WIFEXITED(status)) << err;
    ASSERT_EQ(WEXITSTATUS(status), 0) << err;
    const json::value s = json::parse(read_text(out / "summary.json"));
    const json::array& tests = s.at("tests").as_array();
    ASSERT_EQ(tests.size(), 2u);
    for (const json::value& t : tests) {
        // The lateral walls hold σ₃ (within the servo's band, a few %), and a
        // packing of frictional spheres under load has σ₁ > σ₃.
        const double s3 = t.at("confining_pressure_pa").to_number<double>();
        const json::value& y = t.at("yield");
        EXPECT_NEAR(y.at("sigma3_effective_pa").to_number<double>() / s3, 1.0, 0.1) << json::serialize(t);
        EXPECT_GT(y.at("sigma1_pa").to_number<double>(), 1.2 * s3) << json::serialize(t);
        EXPECT_GT(t.at("peak_deviatoric_stress_pa").to_number<double>(), 0.0);
    }
    EXPECT_TRUE(at(s, {"mohr_coulomb", "friction_angle_deg"}).is_number());
    EXPECT_EQ(at(s, {"specimen", "grains"}).to_number<std::int64_t>(), 150);
    // The compacted box, not a poured column: a random packing's fraction.
    const double phi = at(s, {"specimen", "grain_volume_fraction"}).to_number<double>();
    EXPECT_GT(phi, 0.45);
    EXPECT_LT(phi, 0.65);
    const File f = File::open_read_only(out / "result.h5");
    const auto root = f.root();
    const json::value spec = json::parse(root.open_dataset("job_spec").read_string());
    EXPECT_EQ(at(spec, {"triaxial", "cell"}), "cuboid");
    for (const char* name : {"sigma3_10000", "sigma3_20000"})
        EXPECT_TRUE(root.exists(std::string("tests/") + name)) << name;
    fs::remove_all(dir);
}

// A job with a free-standing test (examples/tiny.json with the test asked
// for): summary.json's free_standing and result.h5's /free_standing say the
// same, the weight the column settles with is its real weight under the
// mass scaling (150 grains of r_p = 1.23 mm, 7800 kg/m³: Σ m g, not s Σ m g),
// and the predicted unconfined strength is the envelope's 2c cos φ/(1 − sin φ).
TEST(Campaign, AFreeStandingTestIsInTheSummaryAndTheResultFile)
{
    const fs::path dir = fresh_dir("free_standing"), out = dir / "out";
    json::object job = json::parse(read_text(source("examples/tiny.json"))).as_object();
    job["triaxial"].as_object()["confining_pressures_pa"] = json::array{10000};
    job["free_standing"] = json::object{{"enabled", true}, {"removal_time_s", 0.01}, {"removal_distance_m", 0.002},
        {"max_settling_time_s", 0.1}, {"dead_load_n", 0.05}, {"dead_load_hold_time_s", 0.01},
        {"plate_speed_m_per_s", 0.02}, {"target_axial_strain", 0.05}, {"sample_interval_s", 0.0005}};
    {
        std::ofstream o(dir / "job.json");
        o << json::serialize(job);
    }
    const int status = run_binary(dir / "job.json", out, dir / "log");
    const std::string err = read_text(dir / "log.stderr");
    ASSERT_TRUE(WIFEXITED(status)) << err;
    ASSERT_EQ(WEXITSTATUS(status), 0) << err;
    EXPECT_TRUE(fs::exists(out / "tests/free_standing.h5"));

    const json::value s = json::parse(read_text(out / "summary.json"));
    const json::value& fsj = at(s, {"free_standing"});
    const double r = 1.23e-3, weight_n = 150 * 7800.0 * 4.0 / 3.0 * std::numbers::pi * r * r * r * 10.0;
    EXPECT_NEAR(at(fsj, {"settling", "weight_n"}).to_number<double>(), weight_n, 1e-9 * weight_n);
    EXPECT_GT(at(fsj, {"settling", "height_before_m"}).to_number<double>(), 0.0);
    EXPECT_TRUE(at(fsj, {"settling", "stands"}).is_bool());
    EXPECT_EQ(at(fsj, {"dead_load", "force_n"}).to_number<double>(), 0.05);
    const json::value& mc = at(s, {"mohr_coulomb"});
    const json::value& predicted = at(fsj, {"compression", "predicted_unconfined_strength_pa"});
    if (mc.at("friction_angle_deg").is_number()) {
        const double phi = mc.at("friction_angle_deg").to_number<double>() * std::numbers::pi / 180.0;
        const double c = mc.at("cohesion_pa").to_number<double>();
        EXPECT_NEAR(predicted.to_number<double>(), 2 * c * std::cos(phi) / (1 - std::sin(phi)), 1e-9 * (std::abs(c) + 1));
    }

    const File f = File::open_read_only(out / "result.h5");
    ASSERT_TRUE(f.root().exists("free_standing"));
    const auto g = f.root().open_group("free_standing");
    EXPECT_DOUBLE_EQ(g.read_double_attribute("weight_n"), at(fsj, {"settling", "weight_n"}).to_number<double>());
    EXPECT_DOUBLE_EQ(g.read_double_attribute("height_loss"), at(fsj, {"settling", "height_loss"}).to_number<double>());
    if (g.has_attribute("strength_smoothed_maximum")) {
        EXPECT_DOUBLE_EQ(g.read_double_attribute("strength_smoothed_maximum"),
            at(fsj, {"compression", "unconfined_strength_pa"}).to_number<double>());
    }
    const std::size_t rows = g.open_dataset("sigma1_pa").shape().at(0);
    EXPECT_GT(rows, 10u);
    EXPECT_EQ(g.open_dataset("phase").shape().at(0), rows);
    EXPECT_EQ(g.open_group("profile_settled").open_dataset("radius_m").read_string_attribute("units"), "m");
    fs::remove_all(dir);
}

// A job that pulls the wire out of its free-standing column instead of the
// compression (the web test's job, examples/tiny.json with a helix, its
// top end pulled up by 3 mm):
// summary.json's free_standing.pull_out and result.h5's /free_standing say
// the same, the rows of the pull are those of the series' phase 4, and the
// compression is left out (null figures). Its triaxial test stops at 1 %
// strain after a 2 ms ramp and a 3 ms hold: only its first snapshot (ε₁ = 0)
// is read, by `wiredem cuts`, and the whole 8 % took 16 times a Release run's
// 19 s under ASan (324 s, CI of 2026-12-06; 177 s at 1 % after the example's
// 5 + 10 ms, which the consolidation check lengthens).
TEST(Campaign, APullOutIsInTheSummaryAndTheResultFile)
{
    const fs::path dir = fresh_dir("pull_out"), out = dir / "out";
    json::object job = json::parse(read_text(source("tests/web/job.json"))).as_object();
    json::object& triaxial = job["triaxial"].as_object();
    triaxial["confining_pressures_pa"] = json::array{10000};
    triaxial["target_axial_strain"] = 0.01;
    triaxial["snapshot_strains"] = json::array{0, 0.01};
    triaxial["pressure_ramp_time_s"] = 0.002;
    triaxial["hold_time_s"] = 0.003;
    job["free_standing"] = json::object{{"enabled", true}, {"removal_time_s", 0.01}, {"removal_distance_m", 0.002},
        {"max_settling_time_s", 0.05}, {"pull_out_speed_m_per_s", 0.05}, {"pull_out_ramp_time_s", 0.005},
        {"pull_out_length_m", 0.003}, {"pull_out_max_time_s", 0.5}, {"sample_interval_s", 0.0005}};
    {
        std::ofstream o(dir / "job.json");
        o << json::serialize(job);
    }
    const int status = run_binary(dir / "job.json", out, dir / "log");
    const std::string err = read_text(dir / "log.stderr");
    ASSERT_TRUE(WIFEXITED(status)) << err;
    ASSERT_EQ(WEXITSTATUS(status), 0) << err;

    const json::value s = json::parse(read_text(out / "summary.json"));
    const json::value& p = at(s, {"free_standing", "pull_out"});
    EXPECT_EQ(at(p, {"end"}).as_string(), "length");
    EXPECT_GE(at(p, {"pulled_length_m"}).to_number<double>(), 0.003);
    EXPECT_GT(at(p, {"peak_pull_force_n"}).to_number<double>(), 0.0);
    EXPECT_GT(at(p, {"wire_in_column_before_m"}).to_number<double>(), 0.0);
    EXPECT_TRUE(at(s, {"free_standing", "compression", "unconfined_strength_pa"}).is_null());

    const File f = File::open_read_only(out / "result.h5");
    const auto g = f.root().open_group("free_standing");
    EXPECT_EQ(g.read_string_attribute("pull_out_end"), "length");
    EXPECT_DOUBLE_EQ(g.read_double_attribute("pull_out_peak_force_n"), at(p, {"peak_pull_force_n"}).to_number<double>());
    const auto rows = g.open_group("pull_out");
    const std::vector<double> force = rows.open_dataset("pull_force_n").read_doubles();
    EXPECT_EQ(rows.open_dataset("pull_force_n").read_string_attribute("units"), "N");
    ASSERT_FALSE(force.empty());
    EXPECT_DOUBLE_EQ(*std::max_element(force.begin(), force.end()), at(p, {"peak_pull_force_n"}).to_number<double>());
    std::size_t pull_rows = 0;
    for (std::int64_t phase : g.open_dataset("phase").read_int64s()) pull_rows += phase == 4 ? 1 : 0;
    EXPECT_EQ(pull_rows, force.size());

    // `wiredem cuts` on this result: the two places of lowest strain of the
    // test's first snapshot at least 1 cm apart and from the ends, which the
    // test reads from the same snapshot by brute force.
    const std::string command = std::string(WIREDEM_BIN) + " cuts " + out.string()
                              + " --count 2 --min-spacing-m 0.01 --at-strain 0 2>&1";
    std::string text;
    if (FILE* pipe = ::popen(command.c_str(), "r")) {
        char buf[4096];
        while (const std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) text.append(buf, n);
        EXPECT_EQ(::pclose(pipe), 0) << text;
    }
    const json::value cuts = json::parse(text);
    const auto test = f.root().open_group("tests").child_names().front();
    const std::vector<double> strain
        = f.root().open_group("tests/" + test + "/snapshots/snapshot_0").open_dataset("wire_segment_strain").read_doubles();
    const double l_w = 1.25e-3, spacing = 0.01;
    const std::size_t n = strain.size();
    std::size_t best = n, second = n;
    for (std::size_t s = 0; s < n; ++s) { // the lowest allowed segment, then the lowest 8 or more segments from it
        const double at = (s + 0.5) * l_w;
        if (at < spacing || (n - s - 0.5) * l_w < spacing) continue;
        if (best == n || strain[s] < strain[best]) best = s;
    }
    for (std::size_t s = 0; s < n; ++s) {
        const double at = (s + 0.5) * l_w;
        if (at < spacing || (n - s - 0.5) * l_w < spacing || (s > best ? s - best : best - s) * l_w < spacing) continue;
        if (second == n || strain[s] < strain[second]) second = s;
    }
    ASSERT_LT(second, n);
    const json::array& at = cuts.at("cuts_at_m").as_array();
    ASSERT_EQ(at.size(), 2u) << text;
    EXPECT_DOUBLE_EQ(at[0].to_number<double>(), (std::min(best, second) + 0.5) * l_w) << text;
    EXPECT_DOUBLE_EQ(at[1].to_number<double>(), (std::max(best, second) + 0.5) * l_w) << text;
    EXPECT_EQ(cuts.at("test").as_string(), test);
    fs::remove_all(dir);
}

TEST(Campaign, SigtermStopsTheRunWithinASecondWithExitCode143)
{
    const fs::path dir = fresh_dir("sigterm");
    pid_t pid = 0;
    ASSERT_EQ(run_binary(source("examples/tiny.json"), dir / "out", dir / "log", &pid, false), 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_EQ(::kill(pid, SIGTERM), 0);
    int status = 0;
    waitpid(pid, &status, 0);
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 143);
    EXPECT_LT(waited, 1.0);
    EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));
    fs::remove_all(dir);
}
