// The campaign's records read back exactly what was written (files.hpp): a
// test's result with its series, strength and snapshots, a driver state, a
// preparation report; what a running job's directory holds of a test so far;
// and a damaged record is an error, not a crash. The free-standing test's
// driver state, with its partial record.
#include "files.hpp"
#include "h5_compare.hpp"
#include "io/snapshot.hpp"
#include "result_file_names.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

namespace fs = std::filesystem;
namespace eng = wiredem::engine;
namespace io = wiredem::engine::io;
using wiredem::campaign::read_cuboid_driver_state;
using wiredem::campaign::read_driver_state;
using wiredem::campaign::read_preparation_report;
using wiredem::campaign::read_preparation_state;
using wiredem::campaign::read_test_so_far;
using wiredem::campaign::read_triaxial_result;
using wiredem::campaign::write_cuboid_driver_state;
using wiredem::campaign::write_driver_state;
using wiredem::campaign::write_preparation_report;
using wiredem::campaign::write_preparation_state;
using wiredem::campaign::write_triaxial_result;

namespace {

fs::path temp_file(const std::string& name)
{
    return fs::temp_directory_path() / ("wiredem_files_" + name + "_" + std::to_string(::getpid()) + ".h5");
}

/// A value that differs for every call: a record whose fields are all
/// different, so that a field read into another's place shows.
double next_value()
{
    static double v = 0.1;
    v = v * 1.37 + 0.011;
    return v;
}

eng::TriaxialResult sample_result(std::size_t rows)
{
    eng::TriaxialResult r;
    for (std::size_t i = 0; i < rows; ++i) {
        eng::TriaxialSample s;
        s.time_s = next_value();
        s.phase = static_cast<eng::TriaxialPhase>(i % 3);
        s.axial_strain = next_value();
        s.height_m = next_value();
        s.top_plate_force_n = next_value();
        s.bottom_plate_force_n = next_value();
        s.column_radius_m = next_value();
        s.confining_pressure_pa = next_value();
        s.sigma1_pa = next_value();
        s.sigma3_effective_pa = next_value();
        s.deviatoric_stress_pa = next_value();
        s.stress_ratio = next_value();
        s.kinetic_energy_j = next_value();
        s.elastic_energy_j = next_value();
        s.contacts = 100 + i;
        s.sliding_contacts = 10 + i;
        s.membrane_contacts = 20 + i;
        s.wire_strain_mean = next_value();
        s.wire_strain_max = next_value();
        s.inertial_number = next_value();
        r.series.push_back(s);
    }
    r.series.volumetric_strain.assign(rows, 0.0);
    for (double& v : r.series.volumetric_strain) v = next_value();
    for (int k = 0; k < 2; ++k) {
        eng::TriaxialSnapshot snap;
        snap.requested_axial_strain = next_value();
        snap.axial_strain = next_value();
        snap.time_s = next_value();
        snap.grain_position_m = {eng::Vec3(next_value(), next_value(), next_value()), eng::Vec3(1, 2, 3)};
        snap.grain_radius_m = {next_value(), next_value()};
        snap.grain_velocity_m_per_s = {eng::Vec3(next_value(), -1, 0), eng::Vec3(0, 0, next_value())};
        snap.wire_node_position_m = {eng::Vec3(next_value(), 0, 0)};
        snap.wire_segment_strain = {};
        snap.membrane_node_position_m = {eng::Vec3(0, next_value(), 0), eng::Vec3(1, 1, 1), eng::Vec3(2, 2, 2)};
        snap.membrane_triangles = {{0, 1, 2}};
        snap.forces.first = {eng::BodyRef(eng::BodyKind::grain, 0)};
        snap.forces.second = {eng::BodyRef(eng::BodyKind::wire, 7)};
        snap.forces.force_n = {eng::Vec3(next_value(), next_value(), next_value())};
        snap.forces.normal_force_n = {next_value()};
        snap.forces.wall = {1};
        snap.forces.wall_body = {eng::BodyRef(eng::BodyKind::membrane, 2)};
        snap.forces.wall_force_n = {eng::Vec3(0, 0, next_value())};
        r.snapshots.push_back(snap);
    }
    r.peak_deviatoric_stress_pa = next_value();
    r.peak_axial_strain = next_value();
    r.peak_sigma1_pa = next_value();
    r.peak_sigma3_effective_pa = next_value();
    r.peak_sample = rows - 1;
    eng::analysis::StrengthReading y;
    y.stress_ratio = {eng::analysis::CurveShape::plateau, 1, next_value(), next_value(), next_value(), next_value()};
    y.deviatoric = {eng::analysis::CurveShape::rising, 2, next_value(), next_value(), next_value(), next_value()};
    y.yield_axial_strain = next_value();
    y.yield_sigma1_pa = next_value();
    y.yield_sigma3_pa = next_value();
    y.residual_stress_ratio = next_value();
    r.strength = y;
    r.initial_height_m = next_value();
    r.initial_volume_m3 = next_value();
    r.verdict = {false, next_value(), next_value(), next_value(), "too fast"};
    r.warnings = {"too fast", "a \"quoted\" warning, with σ₃"};
    r.hold_time_s = next_value();
    r.consolidated_sigma1_pa = next_value();
    r.steps = 123456789;
    r.time_step_s = next_value();
    r.simulated_time_s = next_value();
    r.wall_time_s = next_value();
    return r;
}

void expect_same(const eng::analysis::CurveReading& a, const eng::analysis::CurveReading& b)
{
    EXPECT_EQ(a.shape, b.shape);
    EXPECT_EQ(a.index, b.index);
    EXPECT_EQ(a.value, b.value);
    EXPECT_EQ(a.end_value, b.end_value);
    EXPECT_EQ(a.drop, b.drop);
    EXPECT_EQ(a.end_rise, b.end_rise);
}

void expect_same(const eng::TriaxialResult& a, const eng::TriaxialResult& b)
{
    const eng::TriaxialSeries &sa = a.series, &sb = b.series;
    EXPECT_EQ(sa.time_s, sb.time_s);
    EXPECT_EQ(sa.phase, sb.phase);
    EXPECT_EQ(sa.axial_strain, sb.axial_strain);
    EXPECT_EQ(sa.height_m, sb.height_m);
    EXPECT_EQ(sa.top_plate_force_n, sb.top_plate_force_n);
    EXPECT_EQ(sa.bottom_plate_force_n, sb.bottom_plate_force_n);
    EXPECT_EQ(sa.column_radius_m, sb.column_radius_m);
    EXPECT_EQ(sa.confining_pressure_pa, sb.confining_pressure_pa);
    EXPECT_EQ(sa.sigma1_pa, sb.sigma1_pa);
    EXPECT_EQ(sa.sigma3_effective_pa, sb.sigma3_effective_pa);
    EXPECT_EQ(sa.deviatoric_stress_pa, sb.deviatoric_stress_pa);
    EXPECT_EQ(sa.stress_ratio, sb.stress_ratio);
    EXPECT_EQ(sa.volumetric_strain, sb.volumetric_strain);
    EXPECT_EQ(sa.kinetic_energy_j, sb.kinetic_energy_j);
    EXPECT_EQ(sa.elastic_energy_j, sb.elastic_energy_j);
    EXPECT_EQ(sa.contacts, sb.contacts);
    EXPECT_EQ(sa.sliding_contacts, sb.sliding_contacts);
    EXPECT_EQ(sa.membrane_contacts, sb.membrane_contacts);
    EXPECT_EQ(sa.wire_strain_mean, sb.wire_strain_mean);
    EXPECT_EQ(sa.wire_strain_max, sb.wire_strain_max);
    EXPECT_EQ(sa.inertial_number, sb.inertial_number);
    ASSERT_EQ(a.snapshots.size(), b.snapshots.size());
    for (std::size_t i = 0; i < a.snapshots.size(); ++i) {
        const auto &x = a.snapshots[i], &y = b.snapshots[i];
        EXPECT_EQ(x.requested_axial_strain, y.requested_axial_strain);
        EXPECT_EQ(x.axial_strain, y.axial_strain);
        EXPECT_EQ(x.time_s, y.time_s);
        EXPECT_EQ(x.grain_position_m, y.grain_position_m);
        EXPECT_EQ(x.grain_radius_m, y.grain_radius_m);
        EXPECT_EQ(x.grain_velocity_m_per_s, y.grain_velocity_m_per_s);
        EXPECT_EQ(x.wire_node_position_m, y.wire_node_position_m);
        EXPECT_EQ(x.wire_segment_strain, y.wire_segment_strain);
        EXPECT_EQ(x.membrane_node_position_m, y.membrane_node_position_m);
        EXPECT_EQ(x.membrane_triangles, y.membrane_triangles);
        EXPECT_EQ(x.forces.first, y.forces.first);
        EXPECT_EQ(x.forces.second, y.forces.second);
        EXPECT_EQ(x.forces.force_n, y.forces.force_n);
        EXPECT_EQ(x.forces.normal_force_n, y.forces.normal_force_n);
        EXPECT_EQ(x.forces.wall, y.forces.wall);
        EXPECT_EQ(x.forces.wall_body, y.forces.wall_body);
        EXPECT_EQ(x.forces.wall_force_n, y.forces.wall_force_n);
    }
    EXPECT_EQ(a.peak_deviatoric_stress_pa, b.peak_deviatoric_stress_pa);
    EXPECT_EQ(a.peak_axial_strain, b.peak_axial_strain);
    EXPECT_EQ(a.peak_sigma1_pa, b.peak_sigma1_pa);
    EXPECT_EQ(a.peak_sigma3_effective_pa, b.peak_sigma3_effective_pa);
    EXPECT_EQ(a.peak_sample, b.peak_sample);
    ASSERT_EQ(a.strength.has_value(), b.strength.has_value());
    if (a.strength) {
        expect_same(a.strength->stress_ratio, b.strength->stress_ratio);
        expect_same(a.strength->deviatoric, b.strength->deviatoric);
        EXPECT_EQ(a.strength->yield_axial_strain, b.strength->yield_axial_strain);
        EXPECT_EQ(a.strength->yield_sigma1_pa, b.strength->yield_sigma1_pa);
        EXPECT_EQ(a.strength->yield_sigma3_pa, b.strength->yield_sigma3_pa);
        EXPECT_EQ(a.strength->residual_stress_ratio, b.strength->residual_stress_ratio);
    }
    EXPECT_EQ(a.initial_height_m, b.initial_height_m);
    EXPECT_EQ(a.initial_volume_m3, b.initial_volume_m3);
    EXPECT_EQ(a.verdict.quasi_static, b.verdict.quasi_static);
    EXPECT_EQ(a.verdict.max_inertial_number, b.verdict.max_inertial_number);
    EXPECT_EQ(a.verdict.mean_kinetic_to_elastic, b.verdict.mean_kinetic_to_elastic);
    EXPECT_EQ(a.verdict.max_kinetic_to_elastic, b.verdict.max_kinetic_to_elastic);
    EXPECT_EQ(a.verdict.warning, b.verdict.warning);
    EXPECT_EQ(a.warnings, b.warnings);
    EXPECT_EQ(a.hold_time_s, b.hold_time_s);
    EXPECT_EQ(a.consolidated_sigma1_pa, b.consolidated_sigma1_pa);
    EXPECT_EQ(a.steps, b.steps);
    EXPECT_EQ(a.time_step_s, b.time_step_s);
    EXPECT_EQ(a.simulated_time_s, b.simulated_time_s);
    EXPECT_EQ(a.wall_time_s, b.wall_time_s);
    ASSERT_EQ(a.wire_breaks.size(), b.wire_breaks.size());
    for (std::size_t i = 0; i < a.wire_breaks.size(); ++i) {
        EXPECT_EQ(a.wire_breaks[i].event, b.wire_breaks[i].event);
        EXPECT_EQ(a.wire_breaks[i].test_time_s, b.wire_breaks[i].test_time_s);
        EXPECT_EQ(a.wire_breaks[i].axial_strain, b.wire_breaks[i].axial_strain);
        EXPECT_EQ(a.wire_breaks[i].position_m, b.wire_breaks[i].position_m);
    }
}

} // namespace

TEST(CampaignFiles, ATestsWireBreaksReadBackExactlyAndAWholeWireWritesNone)
{
    const fs::path path = temp_file("breaks");
    eng::TriaxialResult written = sample_result(5);
    const eng::TriaxialResult whole = written;
    written.wire_breaks.push_back({.event = {.segment = 17, .cause = eng::WireBreakCause::strain, .time_s = 1.25,
                                       .strain = 0.0501, .released_energy_j = 3.2e-4},
        .test_time_s = 0.031, .axial_strain = 0.0123, .position_m = 17.5 * 1.25e-3});
    written.wire_breaks.push_back({.event = {.segment = 3, .cause = eng::WireBreakCause::cut, .time_s = 1.5,
                                       .strain = -1e-4, .released_energy_j = 1e-12},
        .test_time_s = 0.0625, .axial_strain = 0.025, .position_m = 3.5 * 1.25e-3});
    io::write_file_atomically(path, [&](io::Group& root) {
        io::Group g = root.create_group("test");
        write_triaxial_result(g, written);
        io::Group h = root.create_group("whole");
        write_triaxial_result(h, whole);
    });
    const io::File f = io::File::open_read_only(path);
    expect_same(read_triaxial_result(f.root().open_group("test")), written);
    EXPECT_FALSE(f.root().open_group("whole").exists("wire_breaks")) << "a whole wire's record is as it was";
    expect_same(read_triaxial_result(f.root().open_group("whole")), whole);
    fs::remove(path);
}

TEST(CampaignFiles, ATestsRecordReadsBackExactly)
{
    const fs::path path = temp_file("result");
    const eng::TriaxialResult written = sample_result(5);
    io::write_file_atomically(path, [&](io::Group& root) {
        io::Group g = root.create_group("test");
        write_triaxial_result(g, written);
    });
    const io::File f = io::File::open_read_only(path);
    expect_same(read_triaxial_result(f.root().open_group("test")), written);
    fs::remove(path);
}

TEST(CampaignFiles, ADriverStateReadsBackExactlyWithItsPartialRecord)
{
    const fs::path path = temp_file("driver");
    eng::TriaxialDriverState s;
    s.steps = 4242;
    s.expected_steps = 99999;
    s.loading = true;
    s.reference_height_m = next_value();
    s.next_snapshot = 2;
    s.loading_start_sample = 1;
    s.window_force_n = next_value();
    s.window_filled = 17;
    s.window_sigma1_pa = next_value();
    s.column_radius_m = next_value();
    s.cap_nodes = {3, 5, 8, 13};
    s.wall_time_s = next_value();
    s.live_springs_reported = true;
    s.result = sample_result(3);
    s.result.series.volumetric_strain.clear(); // a running test has none yet
    s.result.strength.reset();
    for (const bool sampled : {true, false}) {
        s.last_sample_step = sampled ? 4240 : std::numeric_limits<std::uint64_t>::max(); // "none yet" too
        io::write_file_atomically(path, [&](io::Group& root) {
            io::Group g = root.create_group("host");
            write_driver_state(g, s);
        });
        const io::File f = io::File::open_read_only(path);
        const eng::TriaxialDriverState r = read_driver_state(f.root().open_group("host"));
        EXPECT_EQ(r.steps, s.steps);
        EXPECT_EQ(r.expected_steps, s.expected_steps);
        EXPECT_EQ(r.loading, s.loading);
        EXPECT_EQ(r.reference_height_m, s.reference_height_m);
        EXPECT_EQ(r.last_sample_step, s.last_sample_step);
        EXPECT_EQ(r.next_snapshot, s.next_snapshot);
        EXPECT_EQ(r.loading_start_sample, s.loading_start_sample);
        EXPECT_EQ(r.window_force_n, s.window_force_n);
        EXPECT_EQ(r.window_filled, s.window_filled);
        EXPECT_EQ(r.window_sigma1_pa, s.window_sigma1_pa);
        EXPECT_EQ(r.column_radius_m, s.column_radius_m);
        EXPECT_EQ(r.cap_nodes, s.cap_nodes);
        EXPECT_EQ(r.wall_time_s, s.wall_time_s);
        EXPECT_EQ(r.live_springs_reported, s.live_springs_reported);
        expect_same(r.result, s.result);
    }
    fs::remove(path);
}

// A checkpoint written before the driver states kept whether the live
// springs' warning was given (2026-12-07) has no flag: its test gave it
// when one of its warnings is that warning (engine::live_spring_warning), so
// that a test continued from it does not give it again; otherwise not yet.
// With the flag, the flag decides, whatever the warnings say.
TEST(CampaignFiles, ADriverStateWithoutTheSpringsFlagTakesItFromItsWarnings)
{
    using wiredem::campaign::read_free_standing_driver_state;
    using wiredem::campaign::write_free_standing_driver_state;
    const fs::path path = temp_file("driver_before_flag");
    eng::LiveSpringLimit springs;
    springs.critical_s = 2e-6;
    springs.normal_force_n = 3.0;
    springs.stiffness_n_per_m = 3e5;
    springs.omega2_per_s2 = 4e11;
    springs.kinds = "grain–wall";
    const std::string warning = eng::live_spring_warning(springs, 4e-6, "after 1200 steps of the test");
    constexpr const char* flag = "live_springs_reported";
    for (const bool warned : {false, true})
        for (const bool flagged : {false, true}) {
            SCOPED_TRACE(std::string(warned ? "warned" : "not warned") + (flagged ? ", flag kept" : ", no flag"));
            eng::TriaxialDriverState s;
            s.result = sample_result(2);
            if (warned) s.result.warnings.push_back(warning);
            eng::FreeStandingDriverState fs_state;
            fs_state.result.warnings = s.result.warnings;
            // With the flag, it says the opposite of the warnings: the flag wins.
            s.live_springs_reported = fs_state.live_springs_reported = !warned;
            io::write_file_atomically(path, [&](io::Group& root) {
                io::Group g = root.create_group("host");
                write_driver_state(g, s);
                io::Group h = root.create_group("free_standing");
                write_free_standing_driver_state(h, fs_state);
                if (!flagged) { // as written before the flag
                    ASSERT_GE(H5Adelete(g.id(), flag), 0);
                    ASSERT_GE(H5Adelete(h.id(), flag), 0);
                }
            });
            const io::File f = io::File::open_read_only(path);
            const bool expected = flagged ? !warned : warned;
            EXPECT_EQ(read_driver_state(f.root().open_group("host")).live_springs_reported, expected);
            EXPECT_EQ(read_free_standing_driver_state(f.root().open_group("free_standing")).live_springs_reported,
                expected);
        }
    fs::remove(path);
}

// The cuboid cell's state: the membrane cell's, read back as it is (and by
// read_driver_state alone, as the live series reads a running test), and
// the box's rows exactly.
TEST(CampaignFiles, ACuboidDriverStateReadsBackExactlyWithItsBoxRows)
{
    const fs::path path = temp_file("cuboid_driver");
    eng::CuboidDriverState s;
    s.triaxial.steps = 777;
    s.triaxial.reference_height_m = next_value();
    s.triaxial.column_radius_m = next_value();
    s.triaxial.last_sample_step = 770;
    s.triaxial.result = sample_result(3);
    s.triaxial.result.series.volumetric_strain.clear();
    s.triaxial.result.strength.reset();
    for (std::size_t i = 0; i < 3; ++i) {
        s.width_x_m.push_back(next_value());
        s.width_y_m.push_back(next_value());
        s.sigma_x_pa.push_back(next_value());
        s.sigma_y_pa.push_back(next_value());
    }
    io::write_file_atomically(path, [&](io::Group& root) {
        io::Group g = root.create_group("host");
        write_cuboid_driver_state(g, s);
    });
    const io::File f = io::File::open_read_only(path);
    const eng::CuboidDriverState r = read_cuboid_driver_state(f.root().open_group("host"));
    EXPECT_EQ(r.triaxial.steps, s.triaxial.steps);
    EXPECT_EQ(r.triaxial.reference_height_m, s.triaxial.reference_height_m);
    EXPECT_EQ(r.triaxial.column_radius_m, s.triaxial.column_radius_m);
    EXPECT_EQ(r.triaxial.last_sample_step, s.triaxial.last_sample_step);
    EXPECT_TRUE(r.triaxial.cap_nodes.empty());
    expect_same(r.triaxial.result, s.triaxial.result);
    EXPECT_EQ(r.width_x_m, s.width_x_m);
    EXPECT_EQ(r.width_y_m, s.width_y_m);
    EXPECT_EQ(r.sigma_x_pa, s.sigma_x_pa);
    EXPECT_EQ(r.sigma_y_pa, s.sigma_y_pa);
    expect_same(read_driver_state(f.root().open_group("host")).result, s.triaxial.result);
    fs::remove(path);
}

namespace {

/// A free-standing driver state in `phase` with every field set to its own
/// value; with `rows` rows of the partial record (0: a checkpoint taken
/// before the first row, nothing read yet).
eng::FreeStandingDriverState sample_free_standing_state(eng::FreeStandingPhase phase, std::size_t rows)
{
    eng::FreeStandingDriverState s;
    s.steps = 5151;
    s.phase = phase;
    s.phase_start_step = 4000;
    s.reference_height_m = next_value();
    s.reference_radius_m = next_value();
    s.last_sample_step = 5150;
    s.next_snapshot = 1;
    s.max_sigma1_pa = next_value();
    s.profile_at_max_sigma1 = {{next_value(), next_value()}, {next_value(), next_value()}, {3, 4}};
    s.max_window_sigma1_pa = next_value();
    s.below_since_strain = next_value();
    s.loading_begun = true;
    s.window_force_n = next_value();
    s.window_kinetic_energy_j = next_value();
    s.pull_start_m = eng::Vec3(next_value(), -next_value(), next_value());
    s.pull_force_sum_n = next_value();
    s.end_tension_sum_n = next_value();
    s.pull_steps_summed = 7;
    s.wall_time_s = next_value();
    s.live_springs_reported = true;
    eng::FreeStandingResult& r = s.result;
    if (rows > 0) {
        eng::TriaxialResult t = sample_result(rows);
        r.series = t.series;
        r.snapshots = t.snapshots;
        r.peak_snapshot = t.snapshots[0];
        r.loading_start_sample = rows - 1;
    }
    eng::SettlingReading& z = r.settling;
    z.at_rest = true;
    for (double* v : {&z.time_to_rest_s, &z.height_before_m, &z.height_m, &z.height_loss, &z.bulk_height_before_m,
             &z.bulk_height_m, &z.bulk_height_loss, &z.radius_before_m, &z.radius_m, &z.lost_fraction, &z.weight_n,
             &z.base_force_n, &z.base_force_tolerance_n, &z.max_removal_kinetic_energy_j})
        *v = next_value();
    z.grains = 150;
    z.escaped_grains = 3;
    z.profile_before = {{next_value()}, {next_value()}, {9}};
    r.dead_load = eng::DeadLoadReading{next_value(), next_value(), next_value(), next_value(), next_value(), true};
    if (rows > 0) {
        eng::PullOutReading p;
        p.pulled_node = 12;
        p.peak_pull_force_n = next_value();
        p.pulled_length_at_peak_m = next_value();
        p.wire_in_column_before_m = next_value();
        p.end = eng::PullOutEnd::wire_out;
        p.series.time_s = {next_value()};
        p.series.pulled_length_m = {next_value()};
        p.series.pull_force_n = {next_value()};
        p.series.end_tension_n = {next_value()};
        p.series.wire_in_column_m = {next_value()};
        p.series.grains_in_column = {140};
        r.pull_out = p;
        eng::CompressionReading c; // a finished test's (both with a pull-out: the record does not mind)
        c.strength = {eng::analysis::CurveShape::peak, rows - 2, next_value(), next_value(), next_value(), next_value()};
        c.strength_axial_strain = next_value();
        c.max_sigma1_pa = next_value();
        c.max_sigma1_sample = rows - 2;
        c.failed = true;
        c.profile_at_peak = {{next_value()}, {next_value()}, {8}};
        c.profile_at_end = {{next_value(), next_value()}, {next_value(), next_value()}, {8, 1}};
        c.wire_strain_at_peak = {next_value(), next_value()};
        c.wire_tension_at_peak_n = {next_value(), next_value()};
        c.failure_mode = eng::FailureMode::grains_spilling;
        c.spilled_fraction = next_value();
        c.bulge_m = next_value();
        r.compression = c;
    }
    r.wire_breaks.push_back({.event = {.segment = 17, .cause = eng::WireBreakCause::strain, .time_s = 1.25,
                                 .strain = 0.0501, .released_energy_j = 3.2e-4},
        .test_time_s = 0.031, .axial_strain = 0.0123, .position_m = 17.5 * 1.25e-3});
    r.verdict = {false, next_value(), next_value(), next_value(), "too fast"};
    r.warnings = {"not at rest"};
    r.steps = 5151;
    r.time_step_s = next_value();
    r.simulated_time_s = next_value();
    r.wall_time_s = next_value();
    return s;
}

} // namespace

// A free-standing test's checkpoint holds the driver's state and its partial
// record: read back and written again, it is the same file, attribute for
// attribute and bit for bit (every field has its own value, so a field read
// into another's place, or not read, shows), in every phase, before the
// first row, with "no row yet" and "not below the failure level" (NaN).
TEST(CampaignFiles, AFreeStandingDriverStateReadsBackExactlyWithItsPartialRecord)
{
    using wiredem::campaign::read_free_standing_driver_state;
    using wiredem::campaign::write_free_standing_driver_state;
    const fs::path first = temp_file("fs_driver"), again = temp_file("fs_driver_again");
    for (auto phase : {eng::FreeStandingPhase::removal, eng::FreeStandingPhase::settling, eng::FreeStandingPhase::dead_load,
             eng::FreeStandingPhase::loading, eng::FreeStandingPhase::pull_out})
        for (const std::size_t rows : {std::size_t{0}, std::size_t{4}}) {
            SCOPED_TRACE(std::string(eng::to_string(phase)) + ", rows " + std::to_string(rows));
            eng::FreeStandingDriverState s = sample_free_standing_state(phase, rows);
            if (rows == 0) {
                s.last_sample_step = std::numeric_limits<std::uint64_t>::max(); // "none yet"
                s.below_since_strain = std::numeric_limits<double>::quiet_NaN();
            }
            io::write_file_atomically(first, [&](io::Group& root) {
                io::Group g = root.create_group("host");
                write_free_standing_driver_state(g, s);
            });
            eng::FreeStandingDriverState r;
            {
                const io::File f = io::File::open_read_only(first);
                r = read_free_standing_driver_state(f.root().open_group("host"));
            }
            EXPECT_EQ(r.phase, phase);
            EXPECT_EQ(r.steps, s.steps);
            EXPECT_EQ(r.last_sample_step, s.last_sample_step);
            EXPECT_EQ(std::isnan(r.below_since_strain), rows == 0);
            EXPECT_EQ(r.pull_start_m, s.pull_start_m);
            EXPECT_EQ(r.live_springs_reported, s.live_springs_reported);
            EXPECT_EQ(r.result.series.sigma1_pa, s.result.series.sigma1_pa);
            EXPECT_EQ(r.result.wire_breaks.size(), 1u);
            EXPECT_EQ(r.result.pull_out.has_value(), rows > 0);
            ASSERT_EQ(r.result.compression.has_value(), rows > 0);
            if (rows > 0) {
                EXPECT_EQ(r.result.compression->failure_mode, eng::FailureMode::grains_spilling);
                EXPECT_EQ(r.result.compression->bulge_m, s.result.compression->bulge_m);
            }
            io::write_file_atomically(again, [&](io::Group& root) {
                io::Group g = root.create_group("host");
                write_free_standing_driver_state(g, r);
            });
            const std::vector<std::string> diffs = wiredem::test::h5_differences(first, again, {});
            EXPECT_TRUE(diffs.empty()) << (diffs.empty() ? std::string() : diffs.front());
        }
    fs::remove(first);
    fs::remove(again);
}

// What the server's live series read: nothing, then the checkpoint's partial
// record (without its snapshots), then the finished test's file, which wins
// over a checkpoint still beside it. The columns are the record's, in the
// writer's order with its units, ε_v left out while it is empty.
TEST(CampaignFiles, ATestSoFarIsNothingThenItsCheckpointThenItsFile)
{
    using wiredem::campaign::TestSoFar;
    const wiredem::campaign::JobDir dir{fs::temp_directory_path() / ("wiredem_so_far_" + std::to_string(::getpid()))};
    fs::create_directories(dir.tests());
    EXPECT_EQ(read_test_so_far(dir, 1, wiredem::campaign::Snapshots::skip).state, TestSoFar::State::waiting);

    eng::TriaxialDriverState s;
    s.result = sample_result(4);
    s.result.series.volumetric_strain.clear();
    ASSERT_TRUE(eng::save_snapshot(eng::World{}, dir.checkpoint(1), [&](io::Group& host) { write_driver_state(host, s); }).ok());
    const TestSoFar running = read_test_so_far(dir, 1, wiredem::campaign::Snapshots::skip);
    ASSERT_EQ(running.state, TestSoFar::State::running);
    EXPECT_EQ(running.record.series.time_s, s.result.series.time_s);
    EXPECT_EQ(running.record.series.deviatoric_stress_pa, s.result.series.deviatoric_stress_pa);
    EXPECT_TRUE(running.record.snapshots.empty()) << "skipped";
    const auto columns = wiredem::campaign::series_columns(running.record.series);
    ASSERT_FALSE(columns.empty());
    EXPECT_EQ(columns.front().name, "time_s");
    EXPECT_EQ(columns.front().units, "s");
    EXPECT_EQ(columns.back().name, "phase");
    for (const auto& c : columns) {
        EXPECT_NE(c.name, "volumetric_strain");
        EXPECT_EQ(c.values.size(), 4u) << c.name;
    }

    const eng::TriaxialResult done = sample_result(6);
    io::write_file_atomically(dir.test(1), [&](io::Group& root) {
        io::Group g = root.create_group(wiredem::campaign::test_file_group);
        write_triaxial_result(g, done);
    });
    const TestSoFar finished = read_test_so_far(dir, 1, wiredem::campaign::Snapshots::read);
    ASSERT_EQ(finished.state, TestSoFar::State::finished);
    expect_same(finished.record, done);
    EXPECT_EQ(wiredem::campaign::series_columns(finished.record.series).size(), columns.size() + 1) << "with ε_v";
    fs::remove_all(dir.root);
}

TEST(CampaignFiles, APreparationReportReadsBackExactly)
{
    const fs::path path = temp_file("report");
    eng::PreparationReport p;
    p.grains = 8000;
    p.wire_nodes = 7999;
    p.wire_length_m = next_value();
    p.nozzle_path_m = next_value();
    p.pile_height_m = next_value();
    p.sample_volume_m3 = next_value();
    p.grain_volume_fraction = next_value();
    p.wire_volume_fraction = next_value();
    p.core_grain_volume_fraction = next_value();
    p.core_wire_volume_fraction = next_value();
    p.simulated_time_s = next_value();
    p.wall_time_s = next_value();
    p.steps = 360000;
    p.time_step_s = next_value();
    p.settled = true;
    p.top_plate_wall = 3;
    io::write_file_atomically(path, [&](io::Group& g) {
        write_preparation_report(g, p);
    });
    const io::File f = io::File::open_read_only(path);
    const eng::PreparationReport r = read_preparation_report(f.root());
    EXPECT_EQ(r.grains, p.grains);
    EXPECT_EQ(r.wire_nodes, p.wire_nodes);
    EXPECT_EQ(r.wire_length_m, p.wire_length_m);
    EXPECT_EQ(r.nozzle_path_m, p.nozzle_path_m);
    EXPECT_EQ(r.pile_height_m, p.pile_height_m);
    EXPECT_EQ(r.sample_volume_m3, p.sample_volume_m3);
    EXPECT_EQ(r.grain_volume_fraction, p.grain_volume_fraction);
    EXPECT_EQ(r.wire_volume_fraction, p.wire_volume_fraction);
    EXPECT_EQ(r.core_grain_volume_fraction, p.core_grain_volume_fraction);
    EXPECT_EQ(r.core_wire_volume_fraction, p.core_wire_volume_fraction);
    EXPECT_EQ(r.simulated_time_s, p.simulated_time_s);
    EXPECT_EQ(r.wall_time_s, p.wall_time_s);
    EXPECT_EQ(r.steps, p.steps);
    EXPECT_EQ(r.time_step_s, p.time_step_s);
    EXPECT_EQ(r.settled, p.settled);
    EXPECT_EQ(r.top_plate_wall, p.top_plate_wall);
    EXPECT_FALSE(r.grain_sizes.has_value()) << "written only with a grain-size curve";
    fs::remove(path);

    // With a curve: the drawn grains against it.
    eng::GrainSizeReport z;
    for (eng::GradingFigures* f : {&z.requested, &z.drawn}) {
        f->d10_m = next_value();
        f->d50_m = next_value();
        f->d60_m = next_value();
        f->uniformity_coefficient = next_value();
    }
    z.ks_distance = next_value();
    z.ks_critical_1pct = next_value();
    z.grains = 7999;
    p.grain_sizes = z;
    io::write_file_atomically(path, [&](io::Group& g) { write_preparation_report(g, p); });
    const eng::PreparationReport with = read_preparation_report(io::File::open_read_only(path).root());
    ASSERT_TRUE(with.grain_sizes.has_value());
    for (const auto& [a, b] : {std::pair{&with.grain_sizes->requested, &z.requested}, std::pair{&with.grain_sizes->drawn, &z.drawn}}) {
        EXPECT_EQ(a->d10_m, b->d10_m);
        EXPECT_EQ(a->d50_m, b->d50_m);
        EXPECT_EQ(a->d60_m, b->d60_m);
        EXPECT_EQ(a->uniformity_coefficient, b->uniformity_coefficient);
    }
    EXPECT_EQ(with.grain_sizes->ks_distance, z.ks_distance);
    EXPECT_EQ(with.grain_sizes->ks_critical_1pct, z.ks_critical_1pct);
    EXPECT_EQ(with.grain_sizes->grains, z.grains);
    fs::remove(path);
}

TEST(CampaignFiles, APreparationDriverStateReadsBackExactly)
{
    const fs::path path = temp_file("preparation_state");
    for (eng::PreparationPhase phase : {eng::PreparationPhase::pouring, eng::PreparationPhase::settling,
             eng::PreparationPhase::lowering_lid, eng::PreparationPhase::settling_under_lid,
             eng::PreparationPhase::following_lid}) {
        eng::PreparationDriverState s;
        s.phase = phase;
        s.steps = 123457;
        s.rng_state = 0xfedcba9876543210ull; // above the largest int64: written as the same 64 bits
        s.owed_grains = next_value();
        s.next_batch_s = next_value();
        s.poured_volume_m3 = next_value();
        s.pile_top_m = next_value();
        s.nozzle_target_m = next_value();
        s.laid_all = phase != eng::PreparationPhase::pouring;
        s.nozzle.z_m = next_value();
        s.nozzle.path_m = next_value();
        s.nozzle.last_node_path_m = next_value();
        s.nozzle.path_integration = {next_value(), next_value()};
        s.settled_before_lid = phase >= eng::PreparationPhase::lowering_lid;
        s.settled_under_lid = phase == eng::PreparationPhase::following_lid;
        s.top_plate_wall = 2;
        s.wall_time_s = next_value();
        io::write_file_atomically(path, [&](io::Group& g) {
            write_preparation_state(g, s);
        });
        const io::File f = io::File::open_read_only(path);
        const eng::PreparationDriverState r = read_preparation_state(f.root());
        EXPECT_EQ(r.phase, s.phase);
        EXPECT_EQ(r.steps, s.steps);
        EXPECT_EQ(r.rng_state, s.rng_state);
        EXPECT_EQ(r.owed_grains, s.owed_grains);
        EXPECT_EQ(r.next_batch_s, s.next_batch_s);
        EXPECT_EQ(r.poured_volume_m3, s.poured_volume_m3);
        EXPECT_EQ(r.pile_top_m, s.pile_top_m);
        EXPECT_EQ(r.nozzle_target_m, s.nozzle_target_m);
        EXPECT_EQ(r.laid_all, s.laid_all);
        EXPECT_EQ(r.nozzle.z_m, s.nozzle.z_m);
        EXPECT_EQ(r.nozzle.path_m, s.nozzle.path_m);
        EXPECT_EQ(r.nozzle.last_node_path_m, s.nozzle.last_node_path_m);
        EXPECT_EQ(r.nozzle.path_integration.s_m, s.nozzle.path_integration.s_m);
        EXPECT_EQ(r.nozzle.path_integration.theta_rad, s.nozzle.path_integration.theta_rad);
        EXPECT_EQ(r.settled_before_lid, s.settled_before_lid);
        EXPECT_EQ(r.settled_under_lid, s.settled_under_lid);
        EXPECT_EQ(r.top_plate_wall, s.top_plate_wall);
        EXPECT_EQ(r.wall_time_s, s.wall_time_s);
    }
    fs::remove(path);
}

TEST(CampaignFiles, ADamagedRecordIsAnErrorNamingWhatIsWrong)
{
    const fs::path path = temp_file("damaged");
    eng::TriaxialResult r = sample_result(4);
    r.series.sigma1_pa.pop_back(); // one column a row short
    io::write_file_atomically(path, [&](io::Group& root) {
        io::Group g = root.create_group("test");
        write_triaxial_result(g, r);
    });
    const io::File f = io::File::open_read_only(path);
    try {
        (void)read_triaxial_result(f.root().open_group("test"));
        ADD_FAILURE() << "a record with a short column was read";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("differ in length"), std::string::npos) << e.what();
    }
    fs::remove(path);
}

// The writer's functions write only names of the one table of result.h5's
// names (engine/triaxial/result_names.hpp), where the table puts them and with
// its units; and a record with every optional part (strength, consolidation,
// breaks, a free-standing test with dead load, compression, pull-out and
// peak snapshot, grain sizes) writes every name of the places they fill.
// The real binary's result.h5 (specimen, job spec, root): Stages.PrepareTestAnalyseWritesOnlyTheTablesNames.
TEST(CampaignFiles, AResultFileHoldsOnlyTheTablesNames)
{
    using P = eng::ResultPlace;
    const fs::path path = temp_file("names");
    eng::PreparationReport report;
    report.grains = 8;
    eng::GrainSizeReport sizes;
    sizes.grains = 8;
    report.grain_sizes = sizes;
    eng::TriaxialResult test = sample_result(5);
    test.consolidation = eng::Consolidation::effective;
    test.consolidation_target_pa = next_value();
    test.wire_breaks.push_back({.event = {.segment = 3, .cause = eng::WireBreakCause::cut, .time_s = 1.5,
                                    .strain = 0.0, .released_energy_j = 0.0},
        .test_time_s = 0.5, .axial_strain = 0.01, .position_m = 3.5e-3});
    const eng::FreeStandingResult free_standing = sample_free_standing_state(eng::FreeStandingPhase::pull_out, 5).result;
    io::write_file_atomically(path, [&](io::Group& root) {
        root.write_string_attribute(eng::result_name(P::root, "format"), eng::result_format);
        io::Group sp = root.create_group(eng::result_name(P::root, "specimen"));
        write_preparation_report(sp, report);
        wiredem::campaign::write_wire_breaks(sp, test.wire_breaks);
        io::Group t = root.create_group(eng::result_name(P::root, "tests")).create_group(wiredem::campaign::test_group_name(2e4));
        t.write_double_attribute(eng::result_name(P::test, "confining_pressure_pa"), 2e4);
        write_triaxial_result(t, test);
        t.write_string_attribute(eng::result_name(P::record, "peak_failure"), "wire");
        io::Group f = root.create_group(eng::result_name(P::root, "free_standing"));
        wiredem::campaign::write_free_standing_result(f, free_standing);
    });
    const io::File file = io::File::open_read_only(path);
    const wiredem::test::ResultFileNames found = wiredem::test::result_file_names(file.root());
    for (const std::string& p : found.problems) ADD_FAILURE() << p;
    for (const eng::ResultNameSpec& s : eng::result_name_specs) {
        const bool filled = s.place != P::root && s.place != P::specimen && s.place != P::wire_pieces;
        if (filled) {
            EXPECT_TRUE(found.seen.contains({s.place, std::string(s.name)}))
                << s.name << " (" << static_cast<int>(s.place) << ") was not written";
        }
    }
    fs::remove(path);
}
