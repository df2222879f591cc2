// What the client prints for people: the progress bar of `wait` on a
// terminal, durations, and the summary table (also when fields are missing).
#include "display.hpp"

#include <boost/json.hpp>
#include <gtest/gtest.h>

#include <sstream>

namespace wiredem::client {
namespace {
namespace json = boost::json;

TEST(ClientDisplay, ProgressBarShowsFractionStageAndEta)
{
    const json::value job = json::parse(R"({"state": "running", "stage": "testing", "progress": 0.5, "eta_s": 80})");
    const std::string bar = format_progress_bar(job, 10);
    EXPECT_EQ(bar.substr(0, 12), "[=====>    ]");
    EXPECT_NE(bar.find(" 50%"), std::string::npos) << bar;
    EXPECT_NE(bar.find("testing"), std::string::npos) << bar;
    EXPECT_NE(bar.find("eta 1m20s"), std::string::npos) << bar;
    const json::value queued = json::parse(R"({"state": "queued", "stage": null, "progress": 0, "eta_s": null})");
    const std::string q = format_progress_bar(queued, 10);
    EXPECT_NE(q.find("queued"), std::string::npos) << q;
    EXPECT_EQ(q.find("eta"), std::string::npos) << q;
}

TEST(ClientDisplay, NamesAndMessagesCannotDriveTheTerminal)
{
    // Escape sequences, C1 controls, line separators and bidi overrides in a
    // job's name or a runner's message print as visible escapes; ordinary
    // UTF-8 (σ₃, accents) is kept; bytes that are not UTF-8 become \xNN.
    EXPECT_EQ(printable("ok \x1b[2J\x07 bell"), "ok \\x1b[2J\\x07 bell");
    EXPECT_EQ(printable("line\nbreak\ttab"), "line\\x0abreak\\x09tab");
    EXPECT_EQ(printable("c1 \xc2\x9b csi"), "c1 \\u{009b} csi");
    EXPECT_EQ(printable("ls \xe2\x80\xa8 ps \xe2\x80\xa9"), "ls \\u{2028} ps \\u{2029}");
    EXPECT_EQ(printable("abc\xe2\x80\xae" "dcba \xe2\x81\xa6" "x\xe2\x81\xa9"), "abc\\u{202e}dcba \\u{2066}x\\u{2069}");
    EXPECT_EQ(printable("σ₃ = 20 kPa, café"), "σ₃ = 20 kPa, café");
    EXPECT_EQ(printable("bad \xff\xc3 end \xc0\xaf"), "bad \\xff\\xc3 end \\xc0\\xaf");
    // Through the displays: a job list line and a summary's warning.
    const json::value page = json::parse(R"({"jobs": [{"id": "0123456789abcdef01234567", "state": "queued",
        "name": "<img src=x>\u001b]0;owned\u0007\u202e"}]})");
    const std::string list = format_job_list(page);
    EXPECT_EQ(list.find('\x1b'), std::string::npos) << list;
    EXPECT_NE(list.find("\\x1b]0;owned\\x07\\u{202e}"), std::string::npos) << list;
    const std::string table = format_summary(json::parse(R"({"warnings": ["x\u001b[31m"]})"));
    EXPECT_NE(table.find("x\\x1b[31m"), std::string::npos) << table;
}

TEST(ClientDisplay, DurationsReadLikeAClock)
{
    EXPECT_EQ(format_duration(0), "0s");
    EXPECT_EQ(format_duration(59.4), "59s");
    EXPECT_EQ(format_duration(80), "1m20s");
    EXPECT_EQ(format_duration(4000), "1h06m");
    EXPECT_EQ(format_duration(-1), "-");
}

TEST(ClientDisplay, AFlaggedFitIsMarkedWithItsCaveatsAndTheConstrainedFitsBesideIt)
{
    const json::value summary = json::parse(R"({
      "mohr_coulomb": {"friction_angle_deg": 21.3, "cohesion_pa": -2100, "r_squared": 0.97,
        "caveats": [{"code": "negative_cohesion", "message": "negative cohesion c = -2.1 kPa: read it as c = 0"}],
        "nonnegative": {"friction_angle_deg": 19.75, "cohesion_pa": 0, "r_squared": 0.95},
        "cohesionless": {"friction_angle_deg": 19.75, "cohesion_pa": 0, "r_squared": 0.95}},
      "mohr_coulomb_max_q": {"friction_angle_deg": 18.0, "cohesion_pa": 500, "r_squared": null, "caveats": [],
        "nonnegative": {"friction_angle_deg": 18.0, "cohesion_pa": 500, "r_squared": null},
        "cohesionless": {"friction_angle_deg": 18.9, "cohesion_pa": 0, "r_squared": 0.8}}})");
    const std::string table = format_summary(summary);
    const std::size_t yield = table.find("through the yield states"), max_q = table.find("through the maxima of q");
    ASSERT_NE(yield, std::string::npos) << table;
    ASSERT_NE(max_q, std::string::npos) << table;
    const std::string flagged = table.substr(yield, max_q - yield), plain = table.substr(max_q);
    for (const char* expected : {"-2.10 kPa  (!) unconstrained fit", "21.30 deg  (!) unconstrained fit",
             "with c >= 0, phi >= 0  phi = 19.75 deg, c = 0.00 kPa, R^2 = 0.9500",
             "(!) negative cohesion c = -2.1 kPa: read it as c = 0"})
        EXPECT_NE(flagged.find(expected), std::string::npos) << expected << "\n" << table;
    EXPECT_EQ(plain.find("(!)"), std::string::npos) << "a fit without caveats is not marked\n" << table;
    EXPECT_NE(plain.find("fit R^2             -"), std::string::npos) << table;
    EXPECT_NE(plain.find("with c = 0             phi = 18.90 deg, c = 0.00 kPa, R^2 = 0.8000"), std::string::npos) << table;
}

TEST(ClientDisplay, AStudyPointWhoseFitHasCaveatsIsMarked)
{
    const json::value summary = json::parse(R"({"name": "s", "points": [
      {"index": 0, "values": {"seed": 1}, "state": "succeeded", "friction_angle_deg": 21.3, "cohesion_pa": -2100,
       "r_squared": null, "fit_caveats": ["two_pressures", "negative_cohesion"]},
      {"index": 1, "values": {"seed": 2}, "state": "succeeded", "friction_angle_deg": 20.0, "cohesion_pa": 100,
       "r_squared": 0.9, "fit_caveats": []}]})");
    const std::string table = format_study_summary(summary);
    std::istringstream lines(table);
    std::string line, first, second;
    while (std::getline(lines, line)) {
        if (line.find("seed=1") != std::string::npos) first = line;
        if (line.find("seed=2") != std::string::npos) second = line;
    }
    EXPECT_NE(first.find("(!) two_pressures negative_cohesion"), std::string::npos) << table;
    EXPECT_EQ(second.find("(!)"), std::string::npos) << table;
}

TEST(ClientDisplay, TheFreeStandingTestShowsWhetherItStandsAndItsStrengthBesideThePrediction)
{
    const json::value summary = json::parse(R"({"free_standing": {
        "settling": {"stands": false, "at_rest": true, "time_to_rest_s": 0.12, "height_before_m": 0.05, "height_m": 0.04,
                     "height_loss": 0.2, "bulk_height_before_m": 0.048, "bulk_height_m": 0.03, "bulk_height_loss": 0.375,
                     "radius_before_m": 0.01, "radius_m": 0.012, "grains": 140, "escaped_grains": 7, "lost_fraction": 0.05,
                     "weight_n": 1.5, "base_force_n": 1.49, "base_force_tolerance_n": 0.02},
        "dead_load": {"force_n": 7, "holds": true, "creep_strain": 0.0012},
        "compression": {"unconfined_strength_pa": 12345, "shape": "peak", "strain_at_failure": 0.021,
                        "predicted_unconfined_strength_pa": 10000, "quasi_static": true,
                        "failure_mode": "bulging", "spilled_fraction": 0.012, "bulge_m": 0.0015, "peak_failure": "grains"}}})");
    const std::string table = format_summary(summary);
    for (const char* part : {"stands                 no", "grains' bulk height    0.048 m -> 0.03 m (loss 37.5 %)",
             "top (grain or wire)    0.05 m -> 0.04 m (loss 20.0 %)", "grains that left it    7 of 140 (5.0 % of the volume)", "holds yes",
             "creep 0.120 %", "12.345 kPa (peak, at 2.10 % strain)", "10.000 kPa (2c cos phi",
             "how it failed          bulging (grains spilled 1.2 % of the volume, widest slice 0.0015 m wider)",
             "gave way at the peak   grains"})
        EXPECT_NE(table.find(part), std::string::npos) << part << "\n" << table;
    EXPECT_EQ(format_summary(json::object{}).find("Free-standing"), std::string::npos);
}

// With a pull-out the compression's figures (null) give way to the pull's.
TEST(ClientDisplay, APullOutShowsThePeakPullForceInsteadOfTheCompression)
{
    const json::value summary = json::parse(R"({"free_standing": {
        "settling": {"stands": true, "at_rest": true},
        "dead_load": null,
        "compression": {"unconfined_strength_pa": null, "shape": null},
        "pull_out": {"peak_pull_force_n": 0.4926, "pulled_length_at_peak_m": 0.00087, "pulled_length_m": 0.0499,
                     "wire_in_column_before_m": 0.0825, "wire_in_column_m": 0.03, "wire_broke": false, "end": "time"}}})");
    const std::string table = format_summary(summary);
    for (const char* part : {"peak pull force        0.4926 N (at 0.00087 m pulled)", "ended by time",
             "0.0825 m -> 0.03 m", "wire broke no"})
        EXPECT_NE(table.find(part), std::string::npos) << part << "\n" << table;
    EXPECT_EQ(table.find("unconfined strength"), std::string::npos) << table;
}

TEST(ClientDisplay, SummaryTableGivesYieldAndMaxQPerPressureInKpaAndBothEnvelopes)
{
    const json::value summary = json::parse(R"({
      "tests": [{"confining_pressure_pa": 20000, "peak_deviatoric_stress_pa": 81234.5, "peak_axial_strain": 0.0412,
                 "sigma1_pa": 101234.5, "sigma3_effective_pa": 19000, "max_q_shape": "rising",
                 "yield": {"shape": "plateau", "stress_ratio": 0.4567, "axial_strain": 0.0311, "sigma1_pa": 77700,
                           "sigma3_effective_pa": 28900},
                 "residual_stress_ratio": 0.4321}],
      "mohr_coulomb": {"friction_angle_deg": 38.5, "cohesion_pa": 1500, "r_squared": 0.99},
      "mohr_coulomb_max_q": {"friction_angle_deg": 41.75, "cohesion_pa": 2500, "paper_top_line_angle_deg": 33.3},
      "specimen": {"cell": "cuboid", "grain_volume_fraction": 0.61, "wire_volume_fraction": 0.008},
      "warnings": ["fit used two points"]})");
    const std::string table = format_summary(summary);
    for (const char* expected : {"20.0", "0.457", "plateau", "3.11", "77.7", "28.9", "81.2", "rising", "4.12", "0.432",
             "38.50 deg", "1.50 kPa", "41.75 deg", "2.50 kPa", "33.30 deg", "0.6100", "0.00800", "fit used two points",
             "triaxial cell          cuboid (six rigid walls; its side walls confine)"})
        EXPECT_NE(table.find(expected), std::string::npos) << expected << "\n" << table;
    EXPECT_NE(table.find("wire nodes             -"), std::string::npos) << "missing fields print as -\n" << table;
    EXPECT_NE(format_summary(json::object{}).find("(no tests in the summary)"), std::string::npos);
}

} // namespace
} // namespace wiredem::client
