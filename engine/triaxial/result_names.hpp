// The names of result.h5 (docs/results.md): its groups, datasets and
// attributes, where each lives, its units and what it holds. The one list the
// writer (campaign/files.cpp, campaign/stages.cpp) and the C++ readers
// (api/result_data.cpp, api/report.cpp, server/handlers/results.cpp,
// engine/io/xdmf.cpp) name them through: result_name(place, "name") is
// evaluated by the compiler, so a name missing here does not compile. The
// readers that cannot include it (docs/results.md, the Python package, the
// web page) are tested against it, and so is a file the writer wrote
// (tests/campaign/test_result_names.cpp). The time series' columns have their
// own list (series_columns.hpp). Changing a name or a unit changes the file
// format: docs/results.md too.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

namespace wiredem::engine {

/// The value of the root's attribute `format`: the layout's name and version.
inline constexpr std::string_view result_format = "wiredem-result-1";

/// Where a name of result.h5 lives.
enum class ResultPlace : unsigned char {
    root,          ///< the file's root group
    dataset,       ///< on every numeric dataset (its `units`)
    specimen,      ///< /specimen (also /host of specimen.h5: the preparation report)
    grain_sizes,   ///< /specimen/grain_sizes
    wire_pieces,   ///< /specimen/wire_pieces
    wire_breaks,   ///< …/wire_breaks: of /specimen, of a test, of /free_standing
    tests,         ///< /tests
    test,          ///< /tests/sigma3_<σ₃>: a triaxial test's own
    record,        ///< a test's group and /free_standing alike (besides the series: series_columns.hpp)
    snapshots,     ///< …/snapshots
    snapshot,      ///< …/snapshots/snapshot_<k>, /free_standing/peak_snapshot
    free_standing, ///< /free_standing: the free-standing test's own
    profile,       ///< /free_standing/profile_*: a radius profile
    pull_out,      ///< /free_standing/pull_out: the pull-out's rows
};

/// What a name names.
enum class ResultKind : unsigned char { group, dataset, attribute };

/// One name of result.h5.
struct ResultNameSpec {
    ResultPlace place;
    ResultKind kind;
    std::string_view name;     ///< as the file spells it; a group named by number or pressure: the part before it
    std::string_view units;    ///< a dataset's `units` attribute; of an attribute, what its number is in ("" text)
    std::string_view meaning;
};

/// Every name of result.h5 but the series columns, by place.
inline constexpr auto result_name_specs = [] {
    using P = ResultPlace;
    using K = ResultKind;
    return std::array<ResultNameSpec, 178>{{
        // root
        {P::root, K::group, "specimen", "", "the prepared specimen and its preparation report"},
        {P::root, K::group, "tests", "", "one group per triaxial test"},
        {P::root, K::group, "free_standing", "", "the free-standing test, when the job ran it"},
        {P::root, K::attribute, "format", "", "the file format's name and version: \"wiredem-result-1\""},
        {P::root, K::dataset, "job_spec", "", "the job spec as JSON text (api::to_json, every field)"},
        // dataset
        {P::dataset, K::attribute, "units", "", "of every numeric dataset: its units (\"1\" dimensionless, a count or an index)"},
        // specimen
        {P::specimen, K::attribute, "grains", "1", "grains poured"},
        {P::specimen, K::attribute, "wire_nodes", "1", "nodes of the wire laid"},
        {P::specimen, K::attribute, "wire_length_m", "m", "rest length of the wire laid"},
        {P::specimen, K::attribute, "nozzle_path_m", "m", "length of the nozzle's path"},
        {P::specimen, K::attribute, "pile_height_m", "m", "height of the settled pile"},
        {P::specimen, K::attribute, "sample_volume_m3", "m³", "volume of the column, π R² h"},
        {P::specimen, K::attribute, "grain_volume_fraction", "1", "grain volume / sample volume"},
        {P::specimen, K::attribute, "wire_volume_fraction", "1", "wire volume / sample volume"},
        {P::specimen, K::attribute, "core_grain_volume_fraction", "1", "the same in the core, away from the membrane and plates"},
        {P::specimen, K::attribute, "core_wire_volume_fraction", "1", "the same of the wire"},
        {P::specimen, K::attribute, "simulated_time_s", "s", "simulated time of the preparation"},
        {P::specimen, K::attribute, "wall_time_s", "s", "wall-clock time of the preparation (differs run to run)"},
        {P::specimen, K::attribute, "steps", "1", "time steps of the preparation"},
        {P::specimen, K::attribute, "time_step_s", "s", "the preparation's time step"},
        {P::specimen, K::attribute, "settled", "1", "1 when the pile settled within the time allowed, else 0"},
        {P::specimen, K::attribute, "top_plate_wall", "1", "index of the top plate among the World's walls (the lid the tests load with)"},
        {P::specimen, K::group, "grain_sizes", "", "with a grain-size curve: the drawn grains against the requested curve"},
        {P::specimen, K::dataset, "grain_position_m", "m", "N×3: the grains' centres"},
        {P::specimen, K::dataset, "grain_radius_m", "m", "N: the grains' radii"},
        {P::specimen, K::dataset, "grain_clump", "1", "N, with clumps only: the clump of each sphere, −1 for a free grain"},
        {P::specimen, K::dataset, "wire_node_position_m", "m", "W×3: the wire's nodes"},
        {P::specimen, K::dataset, "wire_rest_angle_rad", "rad", "W: the rest angle ζ₀ of each node's plastic joint, 0 at the two ends"},
        {P::specimen, K::dataset, "membrane_node_position_m", "m", "M×3: the membrane's nodes"},
        {P::specimen, K::group, "wire_pieces", "", "a breakable or cut wire only: its pieces"},
        {P::specimen, K::group, "wire_breaks", "", "a breakable or cut wire only: the segments removed in the preparation"},
        // grain_sizes
        {P::grain_sizes, K::attribute, "requested_d10_m", "m", "d10 of the requested curve"},
        {P::grain_sizes, K::attribute, "requested_d50_m", "m", "d50 of the requested curve"},
        {P::grain_sizes, K::attribute, "requested_d60_m", "m", "d60 of the requested curve"},
        {P::grain_sizes, K::attribute, "requested_uniformity_coefficient", "1", "d60/d10 of the requested curve"},
        {P::grain_sizes, K::attribute, "drawn_d10_m", "m", "d10 of the drawn grains"},
        {P::grain_sizes, K::attribute, "drawn_d50_m", "m", "d50 of the drawn grains"},
        {P::grain_sizes, K::attribute, "drawn_d60_m", "m", "d60 of the drawn grains"},
        {P::grain_sizes, K::attribute, "drawn_uniformity_coefficient", "1", "d60/d10 of the drawn grains"},
        {P::grain_sizes, K::attribute, "ks_distance", "1", "Kolmogorov-Smirnov distance of the drawn grains from the curve"},
        {P::grain_sizes, K::attribute, "ks_critical_1pct", "1", "its critical value at the 1 % level"},
        {P::grain_sizes, K::attribute, "grains", "1", "grains drawn"},
        // wire_pieces
        {P::wire_pieces, K::dataset, "first_node", "1", "one per piece: its first node"},
        {P::wire_pieces, K::dataset, "nodes", "1", "its nodes"},
        {P::wire_pieces, K::dataset, "rest_length_m", "m", "its rest length"},
        {P::wire_pieces, K::dataset, "length_m", "m", "its length as laid"},
        // wire_breaks
        {P::wire_breaks, K::dataset, "segment", "1", "one per removed segment, in order: the segment"},
        {P::wire_breaks, K::dataset, "cause", "0 broke (strain past the breaking strain), 1 cut", "why it was removed"},
        {P::wire_breaks, K::dataset, "time_s", "s", "when, since the test started (the World's clock in /specimen)"},
        {P::wire_breaks, K::dataset, "world_time_s", "s", "when, on the World's clock"},
        {P::wire_breaks, K::dataset, "axial_strain", "1", "the test's axial strain after that step (0 in /specimen)"},
        {P::wire_breaks, K::dataset, "position_m", "m", "rest length from the first node to the segment's middle"},
        {P::wire_breaks, K::dataset, "segment_strain", "1", "the segment's strain when it broke"},
        {P::wire_breaks, K::dataset, "released_energy_j", "J", "the elastic energy the segment held"},
        // tests
        {P::tests, K::group, "sigma3_", "", "followed by σ₃ in Pa to 17 significant digits (sigma3_20000): one test"},
        // test
        {P::test, K::attribute, "confining_pressure_pa", "Pa", "the test's σ₃"},
        {P::test, K::attribute, "peak_deviatoric_stress_pa", "Pa", "the raw maximum of q over the loading"},
        {P::test, K::attribute, "peak_axial_strain", "1", "the axial strain there"},
        {P::test, K::attribute, "peak_sigma1_pa", "Pa", "σ₁ there"},
        {P::test, K::attribute, "peak_sigma3_effective_pa", "Pa", "σ₃,eff there"},
        {P::test, K::attribute, "peak_sample", "1", "its row of the series"},
        {P::test, K::attribute, "yield_shape", "", "the stress-ratio curve's shape: peak, plateau or rising (absent when it cannot be read)"},
        {P::test, K::attribute, "yield_sample", "1", "the row of its smoothed maximum"},
        {P::test, K::attribute, "yield_smoothed_maximum", "1", "its smoothed maximum"},
        {P::test, K::attribute, "yield_smoothed_end", "1", "its smoothed value at the end"},
        {P::test, K::attribute, "yield_drop", "1", "the drop after the maximum, relative"},
        {P::test, K::attribute, "yield_end_rise", "1", "the rise over the last part, relative"},
        {P::test, K::attribute, "max_q_shape", "", "the same of the q curve"},
        {P::test, K::attribute, "max_q_sample", "1", "the row of q's smoothed maximum"},
        {P::test, K::attribute, "max_q_smoothed_maximum", "Pa", "q's smoothed maximum"},
        {P::test, K::attribute, "max_q_smoothed_end", "Pa", "q's smoothed value at the end"},
        {P::test, K::attribute, "max_q_drop", "1", "its drop after the maximum, relative"},
        {P::test, K::attribute, "max_q_end_rise", "1", "its rise over the last part, relative"},
        {P::test, K::attribute, "yield_stress_ratio", "1", "σ₁/σ₃,eff at yield (the smoothed maximum of the stress ratio)"},
        {P::test, K::attribute, "yield_axial_strain", "1", "the axial strain at yield"},
        {P::test, K::attribute, "yield_sigma1_pa", "Pa", "σ₁ at yield"},
        {P::test, K::attribute, "yield_sigma3_effective_pa", "Pa", "σ₃,eff at yield"},
        {P::test, K::attribute, "residual_stress_ratio", "1", "the stress ratio at the end"},
        {P::test, K::attribute, "hold_time_s", "s", "how long σ₃ was held before the loading"},
        {P::test, K::attribute, "consolidated_sigma1_pa", "Pa", "σ₁ at the end of the consolidation"},
        {P::test, K::attribute, "consolidation", "", "cell_pressure or effective (absent in files written before 2026-12-03)"},
        {P::test, K::attribute, "consolidation_target_pa", "Pa", "the consolidation's target"},
        {P::test, K::attribute, "initial_height_m", "m", "the column's height when the loading began"},
        {P::test, K::attribute, "initial_volume_m3", "m³", "its volume then"},
        // record
        {P::record, K::attribute, "quasi_static", "1", "1 when the test was quasi-static (the verdict), else 0"},
        {P::record, K::attribute, "max_inertial_number", "1", "the largest inertial number over the loading"},
        {P::record, K::attribute, "mean_kinetic_to_elastic", "1", "the mean kinetic / elastic energy over the loading (the criterion)"},
        {P::record, K::attribute, "max_kinetic_to_elastic", "1", "its largest sample"},
        {P::record, K::attribute, "quasi_static_warning", "", "empty when quasi-static; otherwise what was exceeded"},
        {P::record, K::attribute, "steps", "1", "time steps of the test"},
        {P::record, K::attribute, "time_step_s", "s", "its time step"},
        {P::record, K::attribute, "simulated_time_s", "s", "its simulated time"},
        {P::record, K::attribute, "wall_time_s", "s", "its wall-clock time (differs run to run)"},
        {P::record, K::attribute, "warnings", "", "JSON array of the test's warnings"},
        {P::record, K::attribute, "peak_failure", "", "a breakable wire only: what gave way at the peak (grains, wire, grains_after_break)"},
        {P::record, K::group, "snapshots", "", "the snapshots, in ascending strain"},
        {P::record, K::group, "wire_breaks", "", "only when the wire broke during the test"},
        // snapshots
        {P::snapshots, K::group, "snapshot_", "", "followed by k = 0, 1, …: one snapshot"},
        // snapshot
        {P::snapshot, K::attribute, "requested_axial_strain", "1", "the axial strain it was taken for"},
        {P::snapshot, K::attribute, "axial_strain", "1", "the axial strain it was taken at"},
        {P::snapshot, K::attribute, "time_s", "s", "the test's time then"},
        {P::snapshot, K::dataset, "grain_position_m", "m", "N×3: the grains' centres"},
        {P::snapshot, K::dataset, "grain_radius_m", "m", "N: their radii"},
        {P::snapshot, K::dataset, "grain_velocity_m_per_s", "m/s", "N×3: their velocities"},
        {P::snapshot, K::dataset, "wire_node_position_m", "m", "W×3: the wire's nodes"},
        {P::snapshot, K::dataset, "wire_segment_strain", "1", "W−1: the strain of each segment"},
        {P::snapshot, K::dataset, "membrane_node_position_m", "m", "M×3: the membrane's nodes"},
        {P::snapshot, K::dataset, "membrane_triangles", "1", "T×3: the membrane's triangles, node indices"},
        {P::snapshot, K::dataset, "contact_bodies", "1", "P×4: kind, index, kind, index of each contact (kinds 0 grain, 1 wire, 2 membrane)"},
        {P::snapshot, K::dataset, "contact_force_n", "N", "P×3: the force on the first body"},
        {P::snapshot, K::dataset, "contact_normal_force_n", "N", "P: its normal part"},
        {P::snapshot, K::dataset, "wall_contact_bodies", "1", "C×3: wall, kind, index of each wall contact"},
        {P::snapshot, K::dataset, "wall_contact_force_n", "N", "C×3: the force on the body"},
        // free_standing
        {P::free_standing, K::attribute, "at_rest", "1", "1 when the column came to rest after the removal"},
        {P::free_standing, K::attribute, "time_to_rest_s", "s", "how long that took"},
        {P::free_standing, K::attribute, "height_before_m", "m", "the column's top before the removal"},
        {P::free_standing, K::attribute, "height_m", "m", "its top, settled"},
        {P::free_standing, K::attribute, "height_loss", "1", "the relative loss of height"},
        {P::free_standing, K::attribute, "bulk_height_before_m", "m", "the bulk's height before the removal"},
        {P::free_standing, K::attribute, "bulk_height_m", "m", "the bulk's height, settled"},
        {P::free_standing, K::attribute, "bulk_height_loss", "1", "its relative loss"},
        {P::free_standing, K::attribute, "radius_before_m", "m", "the column's radius before the removal"},
        {P::free_standing, K::attribute, "radius_m", "m", "its radius, settled"},
        {P::free_standing, K::attribute, "grains", "1", "the grains of the column"},
        {P::free_standing, K::attribute, "escaped_grains", "1", "those that left it"},
        {P::free_standing, K::attribute, "lost_fraction", "1", "escaped_grains / grains"},
        {P::free_standing, K::attribute, "weight_n", "N", "the column's weight"},
        {P::free_standing, K::attribute, "base_force_n", "N", "the force on the base, settled"},
        {P::free_standing, K::attribute, "base_force_tolerance_n", "N", "the tolerance it is held to against the weight"},
        {P::free_standing, K::attribute, "stands", "1", "1 when the column stands"},
        {P::free_standing, K::attribute, "max_removal_kinetic_energy_j", "J", "the largest kinetic energy during the removal"},
        {P::free_standing, K::attribute, "dead_load_n", "N", "the dead load's force"},
        {P::free_standing, K::attribute, "dead_load_stress_pa", "Pa", "its stress on the column"},
        {P::free_standing, K::attribute, "dead_load_strain_at_load", "1", "the axial strain once loaded"},
        {P::free_standing, K::attribute, "dead_load_strain_at_end", "1", "the axial strain at the end of the hold"},
        {P::free_standing, K::attribute, "dead_load_creep_strain", "1", "their difference"},
        {P::free_standing, K::attribute, "dead_load_holds", "1", "1 when the column held the load"},
        {P::free_standing, K::attribute, "strength_shape", "", "the σ₁ curve's shape: peak, plateau or rising"},
        {P::free_standing, K::attribute, "strength_sample", "1", "the row of its smoothed maximum"},
        {P::free_standing, K::attribute, "strength_smoothed_maximum", "Pa", "the unconfined strength"},
        {P::free_standing, K::attribute, "strength_smoothed_end", "Pa", "the smoothed σ₁ at the end"},
        {P::free_standing, K::attribute, "strength_drop", "1", "the drop after the maximum, relative"},
        {P::free_standing, K::attribute, "strength_end_rise", "1", "the rise over the last part, relative"},
        {P::free_standing, K::attribute, "strength_axial_strain", "1", "the axial strain at the strength"},
        {P::free_standing, K::attribute, "max_sigma1_pa", "Pa", "the raw largest σ₁"},
        {P::free_standing, K::attribute, "max_sigma1_sample", "1", "its row"},
        {P::free_standing, K::attribute, "failed", "1", "1 when the column failed"},
        {P::free_standing, K::attribute, "failure_mode", "", "wire_break, grains_spilling, bulging or unresolved (since 2026-12-06)"},
        {P::free_standing, K::attribute, "spilled_fraction", "1", "the fraction of grains spilled"},
        {P::free_standing, K::attribute, "bulge_m", "m", "the largest bulge of the radius"},
        {P::free_standing, K::attribute, "loading_start_sample", "1", "the first row of the compression, or of the pull-out"},
        {P::free_standing, K::attribute, "pull_out_end", "", "why the pull-out ended: length, wire_out, time or host"},
        {P::free_standing, K::attribute, "pull_out_node", "1", "the node pulled"},
        {P::free_standing, K::attribute, "pull_out_peak_force_n", "N", "the largest pull force"},
        {P::free_standing, K::attribute, "pull_out_length_at_peak_m", "m", "the length pulled then"},
        {P::free_standing, K::attribute, "pull_out_length_m", "m", "the length pulled in all"},
        {P::free_standing, K::attribute, "pull_out_wire_in_column_before_m", "m", "the wire in the column before"},
        {P::free_standing, K::attribute, "pull_out_wire_in_column_m", "m", "the wire in the column after"},
        {P::free_standing, K::attribute, "pull_out_grains_in_column", "1", "the grains in the column after"},
        {P::free_standing, K::attribute, "pull_out_wire_broke", "1", "1 when the wire broke"},
        {P::free_standing, K::attribute, "pull_out_ramp_inertia_n", "N", "the force the ramp's acceleration takes"},
        {P::free_standing, K::group, "profile_before", "", "the radius profile before the removal"},
        {P::free_standing, K::group, "profile_settled", "", "settled"},
        {P::free_standing, K::group, "profile_at_peak", "", "at the largest σ₁"},
        {P::free_standing, K::group, "profile_at_end", "", "at the end"},
        {P::free_standing, K::dataset, "wire_strain_at_peak", "1", "per segment, the strain at the largest σ₁"},
        {P::free_standing, K::dataset, "wire_tension_at_peak_n", "N", "per segment, the tension at the largest σ₁"},
        {P::free_standing, K::group, "pull_out", "", "the pull-out's rows, one per series row of its phase"},
        {P::free_standing, K::group, "peak_snapshot", "", "the snapshot at the largest σ₁, laid out as a test's"},
        // profile
        {P::profile, K::dataset, "height_m", "m", "per slice of a grain diameter: its height"},
        {P::profile, K::dataset, "radius_m", "m", "the column's radius there"},
        {P::profile, K::dataset, "grains", "1", "the grains in the slice"},
        // pull_out
        {P::pull_out, K::dataset, "time_s", "s", "the row's time"},
        {P::pull_out, K::dataset, "pulled_length_m", "m", "the length pulled"},
        {P::pull_out, K::dataset, "pull_force_n", "N", "the pull force, mean over the row's sample interval"},
        {P::pull_out, K::dataset, "end_tension_n", "N", "the tension at the pulled end, mean likewise"},
        {P::pull_out, K::dataset, "wire_in_column_m", "m", "the wire in the column"},
        {P::pull_out, K::dataset, "grains_in_column", "1", "the grains in the column"},
    }};
}();

/// The groups named by a number or a pressure: their names begin with the
/// entry's name (snapshot_0, sigma3_20000).
[[nodiscard]] constexpr bool result_name_is_prefix(const ResultNameSpec& s)
{
    return s.kind == ResultKind::group && s.name.ends_with('_');
}

/// The name `name` of `place`; evaluated by the compiler, so that a name not
/// in result_name_specs is a compile error.
[[nodiscard]] consteval const ResultNameSpec& result_name_spec(ResultPlace place, std::string_view name)
{
    for (const ResultNameSpec& s : result_name_specs)
        if (s.place == place && s.name == name) return s;
    throw "not a name of result_name_specs";  // a compile error in a consteval call
}

/// Its spelling: g.write_double_attribute(result_name(ResultPlace::test, "peak_sample"), …).
[[nodiscard]] consteval std::string_view result_name(ResultPlace place, std::string_view name)
{
    return result_name_spec(place, name).name;
}

/// Whether each place names each name once.
[[nodiscard]] consteval bool result_names_are_unique()
{
    for (std::size_t i = 0; i < result_name_specs.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (result_name_specs[i].place == result_name_specs[j].place
                && result_name_specs[i].name == result_name_specs[j].name)
                return false;
    return true;
}
static_assert(result_names_are_unique());

} // namespace wiredem::engine
