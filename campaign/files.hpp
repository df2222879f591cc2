// The files of one job directory, and how the campaign's records are written
// to and read from HDF5 (engine/io/hdf5.hpp).
//
//   DIR/job.json                   the job spec (api::to_json), written first by `prepare`
//   DIR/specimen.h5                the prepared World (io/snapshot.hpp) and, in /host,
//                                  the preparation report
//   DIR/specimen.checkpoint.h5     a running preparation: the World and, in /host, the
//                                  driver's state (engine::PreparationDriverState)
//   DIR/tests/test_K.h5            test K (K-th confining pressure of the job): /test,
//                                  the group result.h5 holds for it
//   DIR/tests/test_K.checkpoint.h5 a running test K: the World and, in /host, the
//                                  driver's state (engine::TriaxialDriverState)
//   DIR/tests/free_standing.h5     the free-standing test (job's free_standing.enabled)
//   DIR/tests/free_standing.checkpoint.h5  a running free-standing test: the World
//                                  and, in /host, engine::FreeStandingDriverState
//   DIR/result.h5, result.xdmf, summary.json   written by `analyse` (docs/results.md)
//   DIR/specimen.lock, DIR/tests/test_K.lock, DIR/analyse.lock
//                                  held by the stage that runs (stage_lock.hpp): one
//                                  process per stage at a time
//
// Every file appears complete or not at all: written beside its name, then
// renamed. Every number is written with its exact bits, so a record read back
// equals the one written (tests/campaign/test_files.cpp) and `analyse`
// writes the same result.h5 and summary.json whether the tests ran in this
// process or in others.
#pragma once

#include "api/result_data.hpp"
#include "io/hdf5.hpp"
#include "specimen/preparation.hpp"
#include "triaxial/cuboid.hpp"
#include "triaxial/free_standing.hpp"
#include "triaxial/result_names.hpp"
#include "triaxial/triaxial.hpp"

#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>

namespace wiredem::campaign {

/// Where each file of a job directory lives.
struct JobDir {
    std::filesystem::path root;

    [[nodiscard]] std::filesystem::path job() const { return root / "job.json"; }
    [[nodiscard]] std::filesystem::path specimen() const { return root / "specimen.h5"; }
    [[nodiscard]] std::filesystem::path specimen_checkpoint() const { return root / "specimen.checkpoint.h5"; }
    [[nodiscard]] std::filesystem::path tests() const { return root / "tests"; }
    [[nodiscard]] std::filesystem::path test(std::size_t k) const;
    [[nodiscard]] std::filesystem::path checkpoint(std::size_t k) const;
    [[nodiscard]] std::filesystem::path result_h5() const { return root / "result.h5"; }
    [[nodiscard]] std::filesystem::path result_xdmf() const { return root / "result.xdmf"; }
    [[nodiscard]] std::filesystem::path summary() const { return root / "summary.json"; }
    // The stages' lock files (stage_lock.hpp).
    [[nodiscard]] std::filesystem::path specimen_lock() const { return root / "specimen.lock"; }
    [[nodiscard]] std::filesystem::path test_lock(std::size_t k) const;
    [[nodiscard]] std::filesystem::path analyse_lock() const { return root / "analyse.lock"; }
    /// The free-standing test's record (group free_standing_file_group) and its lock.
    [[nodiscard]] std::filesystem::path free_standing() const { return tests() / "free_standing.h5"; }
    [[nodiscard]] std::filesystem::path free_standing_lock() const { return tests() / "free_standing.lock"; }
    /// A running free-standing test: the World and, in /host, the driver's
    /// state (engine::FreeStandingDriverState), as a triaxial test's checkpoint.
    [[nodiscard]] std::filesystem::path free_standing_checkpoint() const { return tests() / "free_standing.checkpoint.h5"; }
};

/// The group of free_standing.h5, and of result.h5, that holds the free-standing test.
inline constexpr const char* free_standing_group = api::free_standing_group.data();

/// The group of test_K.h5 that holds the test's record.
inline constexpr const char* test_file_group = "test";

/// The name of a test's group in result.h5: "sigma3_" and the confining
/// pressure in Pa to 17 significant digits ("sigma3_20000", "sigma3_12345.5").
[[nodiscard]] std::string test_group_name(double confining_pressure_pa);

/// Whether a record's snapshots are read: the curves of a running test do
/// not need them, and they are most of a record's bytes.
enum class Snapshots { read, skip };

/// A test's record: attributes (peak, yield, verdict, times, warnings), the
/// time series and the snapshots, as result.h5 holds each test
/// (docs/results.md). Also a partial record (a checkpoint's: no
/// volumetric strain, no peak yet).
/// The wire's breaks of a test, into the group "wire_breaks" of `g` (one
/// dataset per column: segment, cause, time_s of the test, world_time_s,
/// axial_strain, position_m, segment_strain, released_energy_j); nothing when
/// there are none, so a whole wire's files stay as they were.
void write_wire_breaks(engine::io::Group& g, const std::vector<engine::TestWireBreak>& breaks);
/// What write_wire_breaks wrote (none when `g` has no such group). Throws on a malformed group.
[[nodiscard]] std::vector<engine::TestWireBreak> read_wire_breaks(const engine::io::Group& g);

void write_triaxial_result(engine::io::Group& g, const engine::TriaxialResult& r);
/// Reads what write_triaxial_result wrote. Throws (engine::io::Hdf5Error,
/// std::runtime_error) on a missing or misshapen member.
[[nodiscard]] engine::TriaxialResult read_triaxial_result(
    const engine::io::Group& g, Snapshots snapshots = Snapshots::read);

/// The columns of a record's time series with their units, as
/// write_triaxial_result writes them (phase included, counts as numbers). A
/// column a running test's record leaves empty (volumetric_strain, derived
/// when the test ends) is left out.
[[nodiscard]] std::vector<api::SeriesColumn> series_columns(const engine::TriaxialSeries& s);

/// The free-standing test's record (docs/results.md): attributes (the
/// settling, the dead load, the compression's reading, the verdict, times,
/// warnings), the time series (phase: engine::FreeStandingPhase), the radius
/// profiles, the wire at the largest σ₁, the snapshots and the one at the
/// largest σ₁.
void write_free_standing_result(engine::io::Group& g, const engine::FreeStandingResult& r);
/// Reads what write_free_standing_result wrote, also a running test's
/// partial record (a checkpoint's: no rows yet, no compression reading).
/// Throws like read_triaxial_result.
[[nodiscard]] engine::FreeStandingResult read_free_standing_result(const engine::io::Group& g);

/// The test driver's state, its partial result in the subgroup "result".
void write_driver_state(engine::io::Group& g, const engine::TriaxialDriverState& s);
[[nodiscard]] engine::TriaxialDriverState read_driver_state(
    const engine::io::Group& g, Snapshots snapshots = Snapshots::read);

/// The cuboid cell's test driver state: the membrane cell's (write_driver_state,
/// in the same group, so that read_driver_state reads a running cuboid test's
/// record too) and per row the box and its lateral stresses in the subgroup "box".
void write_cuboid_driver_state(engine::io::Group& g, const engine::CuboidDriverState& s);
[[nodiscard]] engine::CuboidDriverState read_cuboid_driver_state(const engine::io::Group& g);

/// The free-standing test driver's state (its phase by name), its partial
/// result in the subgroup "result"; read back with its exact bits.
void write_free_standing_driver_state(engine::io::Group& g, const engine::FreeStandingDriverState& s);
[[nodiscard]] engine::FreeStandingDriverState read_free_standing_driver_state(const engine::io::Group& g);

/// How far test K of a job directory has come, from its own files while the
/// campaign runs: not started (or no checkpoint written yet), running (the
/// record as of its last checkpoint: partial, without volumetric strain or
/// peak) or finished (test_K.h5). Throws like the readers above on a file
/// that does not read.
struct TestSoFar {
    enum class State { waiting, running, finished } state = State::waiting;
    engine::TriaxialResult record;
};
[[nodiscard]] TestSoFar read_test_so_far(const JobDir& dir, std::size_t k, Snapshots snapshots);
[[nodiscard]] std::string_view to_string(TestSoFar::State s);

/// String length per volume: metres of wire per m³ of column (the sample
/// volume π R² h), as printed columns are designed [m/m³]; NaN without a volume.
[[nodiscard]] double wire_length_per_volume_m_per_m3(const engine::PreparationReport& r);

/// Writes the dataset `spec` names (engine/triaxial/result_names.hpp) into
/// `g` with the table's units as its `units` attribute; `values` as
/// engine::io::Group::write_dataset takes them.
template <class... Values>
void write_named(engine::io::Group& g, const engine::ResultNameSpec& spec, Values&&... values)
{
    g.write_dataset(spec.name, std::forward<Values>(values)...)
        .write_string_attribute(engine::result_name(engine::ResultPlace::dataset, "units"), spec.units);
}

/// The preparation report, as attributes (the specimen group of result.h5).
void write_preparation_report(engine::io::Group& g, const engine::PreparationReport& r);
[[nodiscard]] engine::PreparationReport read_preparation_report(const engine::io::Group& g);

/// The preparation driver's state, as attributes (the phase by name).
void write_preparation_state(engine::io::Group& g, const engine::PreparationDriverState& s);
[[nodiscard]] engine::PreparationDriverState read_preparation_state(const engine::io::Group& g);

} // namespace wiredem::campaign
