// The columns of a test's time series (TriaxialSeries, sampling.hpp) as
// result.h5 stores them: name, units, order. The one list the writer and the
// readers go through (campaign/files.cpp writes and reads them, the live
// series route serves them, api/report.cpp and the others name them through
// series_column, which does not compile for a name missing here); the
// consumers that cannot include it (docs/results.md, the web page, the
// Python package) are tested against it (tests/campaign/test_result_schema.cpp).
// Changing a name or a unit changes the file format: docs/results.md too.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

namespace wiredem::engine {

/// One column of a time series.
struct SeriesColumnSpec {
    std::string_view name;   ///< the dataset's name in a test's group (and the member of TriaxialSeries)
    std::string_view units;  ///< its `units` attribute ("1": dimensionless or a count)
};

/// The meaning of a triaxial test's phase column (TriaxialPhase), its `units` attribute.
inline constexpr std::string_view triaxial_phase_units = "0 ramp, 1 hold, 2 loading";
/// The same of the free-standing test's (FreeStandingPhase).
inline constexpr std::string_view free_standing_phase_units = "0 removal, 1 settling, 2 dead_load, 3 loading";
/// … with a pull-out (only then, so that the files of other tests stay as they were).
inline constexpr std::string_view free_standing_pull_out_phase_units =
    "0 removal, 1 settling, 2 dead_load, 3 loading, 4 pull_out";

/// Every column in the order the writer writes them: the numeric columns,
/// then `phase` (integers; its units are the meaning of a test's phases:
/// triaxial_phase_units here, the free-standing test's own).
inline constexpr std::array<SeriesColumnSpec, 21> series_column_specs{{
    {"time_s", "s"},
    {"axial_strain", "1"},
    {"height_m", "m"},
    {"top_plate_force_n", "N"},
    {"bottom_plate_force_n", "N"},
    {"column_radius_m", "m"},
    {"confining_pressure_pa", "Pa"},
    {"sigma1_pa", "Pa"},
    {"sigma3_effective_pa", "Pa"},
    {"deviatoric_stress_pa", "Pa"},
    {"stress_ratio", "1"},
    {"volumetric_strain", "1"},
    {"kinetic_energy_j", "J"},
    {"elastic_energy_j", "J"},
    {"contacts", "1"},
    {"sliding_contacts", "1"},
    {"membrane_contacts", "1"},
    {"wire_strain_mean", "1"},
    {"wire_strain_max", "1"},
    {"inertial_number", "1"},
    {"phase", triaxial_phase_units},
}};

/// The column called `name`; evaluated by the compiler, so that a name not in
/// series_column_specs is a compile error, not a 400 at run time.
[[nodiscard]] consteval const SeriesColumnSpec& series_column(std::string_view name)
{
    for (const SeriesColumnSpec& c : series_column_specs)
        if (c.name == name) return c;
    throw "not a column of series_column_specs";  // a compile error in a consteval call
}

/// Whether every name of series_column_specs is its own.
[[nodiscard]] consteval bool series_column_names_are_unique()
{
    for (std::size_t i = 0; i < series_column_specs.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (series_column_specs[i].name == series_column_specs[j].name) return false;
    return true;
}
static_assert(series_column_names_are_unique());

/// Calls f(spec, column) for every column of `s` (a TriaxialSeries, const or
/// not) but `phase` (bytes in memory, int32 in the file: written apart), in
/// the order of series_column_specs.
template <class Series, class F>
void for_each_series_column(Series& s, F&& f)
{
    f(series_column("time_s"), s.time_s);
    f(series_column("axial_strain"), s.axial_strain);
    f(series_column("height_m"), s.height_m);
    f(series_column("top_plate_force_n"), s.top_plate_force_n);
    f(series_column("bottom_plate_force_n"), s.bottom_plate_force_n);
    f(series_column("column_radius_m"), s.column_radius_m);
    f(series_column("confining_pressure_pa"), s.confining_pressure_pa);
    f(series_column("sigma1_pa"), s.sigma1_pa);
    f(series_column("sigma3_effective_pa"), s.sigma3_effective_pa);
    f(series_column("deviatoric_stress_pa"), s.deviatoric_stress_pa);
    f(series_column("stress_ratio"), s.stress_ratio);
    f(series_column("volumetric_strain"), s.volumetric_strain);
    f(series_column("kinetic_energy_j"), s.kinetic_energy_j);
    f(series_column("elastic_energy_j"), s.elastic_energy_j);
    f(series_column("contacts"), s.contacts);
    f(series_column("sliding_contacts"), s.sliding_contacts);
    f(series_column("membrane_contacts"), s.membrane_contacts);
    f(series_column("wire_strain_mean"), s.wire_strain_mean);
    f(series_column("wire_strain_max"), s.wire_strain_max);
    f(series_column("inertial_number"), s.inertial_number);
}

} // namespace wiredem::engine
