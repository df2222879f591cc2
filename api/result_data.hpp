// What a result.h5 holds (docs/results.md), as JSON: the shapes of the result
// data routes (server/handlers/results.hpp), shared by the server and
// `wiredem report`, which embeds the same data in an offline page. Read from
// the file as the runner wrote it; the only figures computed here are the
// wire autocorrelation of a snapshot (engine::analysis::autocorrelation, the
// function the summary's lag comes from) and the thinning of a series.
// Throws engine::io::Hdf5Error when the file does not read.
#pragma once

#include "io/hdf5.hpp"
#include "triaxial/result_names.hpp"

#include <boost/json/object.hpp>

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace wiredem::api {

/// Largest max_points of a series: more than any plot draws, fewer than a
/// server should serialise per request by mistake.
inline constexpr std::size_t max_series_points = 1'000'000;

/// Name prefix of a test's snapshot groups (snapshot_0, snapshot_1, …).
inline constexpr std::string_view snapshot_prefix = engine::result_name(engine::ResultPlace::snapshots, "snapshot_");

/// Path of snapshot `k` within its test's group: "snapshots/snapshot_<k>".
[[nodiscard]] std::string snapshot_path(std::size_t k);

/// Path of the test `name` (test_names) from the root: "tests/<name>".
[[nodiscard]] std::string test_path(const std::string& name);

/// The tests of a result file by ascending confining pressure (their group
/// names sort as text: sigma3_100000 before sigma3_20000).
[[nodiscard]] std::vector<std::string> test_names(const engine::io::Group& root);

/// Snapshot indices of a test group, ascending.
[[nodiscard]] std::vector<std::size_t> snapshot_indices(const engine::io::Group& test);

/// The time-series columns of a test group: its 1-D numeric datasets.
[[nodiscard]] std::vector<std::string> series_columns(const engine::io::Group& test);

/// Every numeric or string attribute of a group or dataset (non-finite numbers as null).
[[nodiscard]] boost::json::object attributes_of(const engine::io::Object& o);

/// The numeric datasets of a group (specimen or snapshot): name, shape, dtype
/// ("int32" for integers, "float32" otherwise: how the routes send them),
/// units, and url = url_base + "/" + name.
[[nodiscard]] boost::json::array arrays_of(const engine::io::Group& g, const std::string& url_base);

/// {"tests": [{name, rows, attributes, columns: [{name, units}], snapshots:
/// [{…attributes, index, url}], series_url}]}, by ascending pressure; urls
/// under url_base ("/v1/jobs/{id}").
[[nodiscard]] boost::json::object tests_json(const engine::io::Group& root, const std::string& url_base);

/// {test, rows, returned_rows, row_index, units, columns: {name: [...]}} of the
/// given columns (all of series_columns when empty; each must be one of them),
/// thinned to at most max_points rows (decimated_rows).
[[nodiscard]] boost::json::object series_json(const engine::io::Group& test, const std::string& name,
    const std::vector<std::string>& columns, std::size_t max_points);

/// One column of a time series, read already (a running test's record:
/// campaign::series_columns).
struct SeriesColumn {
    std::string name;
    std::optional<std::string> units;  ///< none: the file gives none (null in the reply)
    std::vector<double> values;
};

/// The same reply from columns in memory, in their order; all of equal length.
[[nodiscard]] boost::json::object series_json(const std::string& name, const std::vector<SeriesColumn>& columns,
    std::size_t max_points);

/// {segment_length_m, segments, lag_m, coefficients, mean, variance,
/// first_maximum_lag_m, prominent_maximum_lag_m, error}: the autocorrelation of
/// a wire's segment strains with its first local and first prominent maximum
/// (engine/analysis/autocorrelation.hpp); error (and empty lists) when there is none.
[[nodiscard]] boost::json::object wire_autocorrelation_json(std::span<const double> segment_strain, double segment_length_m);

/// The group of result.h5 that holds a group per triaxial test (test_names).
inline constexpr std::string_view tests_group = engine::result_name(engine::ResultPlace::root, "tests");

/// The group of result.h5 (and of the runner's tests/free_standing.h5) that
/// holds the free-standing test (docs/results.md, campaign/files.hpp writes it).
inline constexpr std::string_view free_standing_group = engine::result_name(engine::ResultPlace::root, "free_standing");

/// The free-standing group's per-segment datasets (the wire at the largest
/// σ₁): 1-D like its series columns, but not of the series' length.
inline constexpr std::array<std::string_view, 2> free_standing_wire_arrays{
    engine::result_name(engine::ResultPlace::free_standing, "wire_strain_at_peak"),
    engine::result_name(engine::ResultPlace::free_standing, "wire_tension_at_peak_n")};

/// Its radius profiles (subgroups of height_m, radius_m, grains per slice):
/// before the removal, settled, at the largest σ₁, at the end.
inline constexpr std::array<std::string_view, 4> free_standing_profiles{
    engine::result_name(engine::ResultPlace::free_standing, "profile_before"),
    engine::result_name(engine::ResultPlace::free_standing, "profile_settled"),
    engine::result_name(engine::ResultPlace::free_standing, "profile_at_peak"),
    engine::result_name(engine::ResultPlace::free_standing, "profile_at_end")};

/// Its peak snapshot's subgroup (the force network at the largest σ₁).
inline constexpr std::string_view free_standing_peak_snapshot =
    engine::result_name(engine::ResultPlace::free_standing, "peak_snapshot");
/// The subgroup of the free-standing test's group that holds a pull-out's
/// rows (time_s, pulled_length_m, pull_force_n, end_tension_n,
/// wire_in_column_m, grains_in_column); its figures are the group's
/// attributes pull_out_* (docs/results.md).
inline constexpr std::string_view pull_out_group = engine::result_name(engine::ResultPlace::free_standing, "pull_out");

/// The free-standing group's time-series columns: its 1-D numeric datasets
/// of the length of its time_s but the wire's per-segment arrays (the
/// triaxial record's volumetric_strain is left empty by this test).
[[nodiscard]] std::vector<std::string> free_standing_series_columns(const engine::io::Group& g);

/// The free-standing test of a group as the routes give it: {name
/// ("free_standing"), rows, attributes (the settling, dead load and
/// compression readings as stored), columns: [{name, units}], profiles:
/// {profile_before: {height_m, radius_m, grains} | null, …}, wire_at_peak:
/// {segment_length_m, distance_m ((k + ½) l_w of segment k), strain,
/// tension_n} | null, snapshots: [{…attributes, index, url}], peak_snapshot:
/// {…attributes, url} | null, series_url}; urls under url_base ("/v1/jobs/{id}").
[[nodiscard]] boost::json::object free_standing_json(
    const engine::io::Group& g, const std::string& url_base, double segment_length_m);

/// Rows kept when a series of `rows` rows is thinned to at most `max_points`
/// (≥ 2): evenly spaced, the first and the last always among them; every row
/// when there are no more than `max_points`.
[[nodiscard]] std::vector<std::size_t> decimated_rows(std::size_t rows, std::size_t max_points);

} // namespace wiredem::api
