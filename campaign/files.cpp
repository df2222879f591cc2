#include "files.hpp"

#include "core/format.hpp"
#include "io/snapshot.hpp"
#include "timestep.hpp"
#include "triaxial/result_names.hpp"
#include "triaxial/series_columns.hpp"

#include <boost/json.hpp>

#include <limits>

#include <algorithm>
#include <array>
#include <cstdint>
#include <fstream>
#include <span>
#include <stdexcept>
#include <string>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

namespace wiredem::campaign {

namespace eng = engine;
namespace io = engine::io;
namespace json = boost::json;

std::filesystem::path JobDir::test(std::size_t k) const { return tests() / ("test_" + std::to_string(k) + ".h5"); }

std::filesystem::path JobDir::checkpoint(std::size_t k) const
{
    return tests() / ("test_" + std::to_string(k) + ".checkpoint.h5");
}

std::filesystem::path JobDir::test_lock(std::size_t k) const { return tests() / ("test_" + std::to_string(k) + ".lock"); }

std::string test_group_name(double pa)
{
    return std::string(eng::result_name(eng::ResultPlace::tests, "sigma3_")) + eng::format_number(pa, 17); // as std::ostream wrote it at precision 17
}

namespace {

void units(io::Dataset d, std::string_view u) { d.write_string_attribute(eng::result_name(eng::ResultPlace::dataset, "units"), u); }

// The names of result.h5 but the series' (engine/triaxial/result_names.hpp):
// the one list the writer and the readers go through.
using P = eng::ResultPlace;
using eng::result_name;
using eng::result_name_spec;


/// The attributes of a curve's reading (engine/analysis/strength.hpp), by
/// the name of the curve in result.h5.
struct CurveNames {
    std::string_view shape, sample, smoothed_maximum, smoothed_end, drop, end_rise;
};
constexpr CurveNames yield_curve{result_name(P::test, "yield_shape"), result_name(P::test, "yield_sample"),
    result_name(P::test, "yield_smoothed_maximum"), result_name(P::test, "yield_smoothed_end"),
    result_name(P::test, "yield_drop"), result_name(P::test, "yield_end_rise")};
constexpr CurveNames max_q_curve{result_name(P::test, "max_q_shape"), result_name(P::test, "max_q_sample"),
    result_name(P::test, "max_q_smoothed_maximum"), result_name(P::test, "max_q_smoothed_end"),
    result_name(P::test, "max_q_drop"), result_name(P::test, "max_q_end_rise")};
constexpr CurveNames strength_curve{result_name(P::free_standing, "strength_shape"),
    result_name(P::free_standing, "strength_sample"), result_name(P::free_standing, "strength_smoothed_maximum"),
    result_name(P::free_standing, "strength_smoothed_end"), result_name(P::free_standing, "strength_drop"),
    result_name(P::free_standing, "strength_end_rise")};

/// A grain-size curve's figures (engine/specimen/grain_sizes.hpp): requested or drawn.
struct GrainSizeNames {
    std::string_view d10_m, d50_m, d60_m, uniformity_coefficient;
};
constexpr GrainSizeNames requested_grain_sizes{result_name(P::grain_sizes, "requested_d10_m"),
    result_name(P::grain_sizes, "requested_d50_m"), result_name(P::grain_sizes, "requested_d60_m"),
    result_name(P::grain_sizes, "requested_uniformity_coefficient")};
constexpr GrainSizeNames drawn_grain_sizes{result_name(P::grain_sizes, "drawn_d10_m"),
    result_name(P::grain_sizes, "drawn_d50_m"), result_name(P::grain_sizes, "drawn_d60_m"),
    result_name(P::grain_sizes, "drawn_uniformity_coefficient")};

// The columns of a time series, their names, units and the meaning of each
// test's phases: engine/triaxial/series_columns.hpp, the one list the writer
// and the readers go through.
using eng::for_each_series_column;
using eng::SeriesColumnSpec;

std::vector<eng::Vec3> read_vec3s(const io::Group& g, std::string_view name)
{
    const io::Dataset d = g.open_dataset(name);
    const std::vector<std::size_t> shape = d.shape();
    if (shape.size() != 2 || shape[1] != 3) throw std::runtime_error(d.path() + ": expected N x 3");
    const std::vector<double> v = d.read_doubles();
    std::vector<eng::Vec3> out(shape[0]);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = eng::Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    return out;
}

/// Rows × `columns` unsigned 32-bit values, row-major (a 1-D dataset when columns is 1).
std::vector<std::uint32_t> read_u32s(const io::Group& g, std::string_view name, std::size_t columns)
{
    const io::Dataset d = g.open_dataset(name);
    const std::vector<std::size_t> shape = d.shape();
    const bool ok = columns == 1 ? shape.size() == 1 : (shape.size() == 2 && shape[1] == columns);
    if (!ok) throw std::runtime_error(d.path() + ": unexpected shape");
    std::vector<std::uint32_t> out;
    for (std::int64_t x : d.read_int64s()) {
        if (x < 0 || x > static_cast<std::int64_t>(UINT32_MAX)) throw std::runtime_error(d.path() + ": value out of range");
        out.push_back(static_cast<std::uint32_t>(x));
    }
    return out;
}

std::vector<double> read_doubles(const io::Group& g, std::string_view name)
{
    const io::Dataset d = g.open_dataset(name);
    if (d.shape().size() != 1) throw std::runtime_error(d.path() + ": expected a 1-D dataset");
    return d.read_doubles();
}

void write_snapshot(io::Group g, const eng::TriaxialSnapshot& s)
{
    g.write_double_attribute(result_name(P::snapshot, "requested_axial_strain"), s.requested_axial_strain);
    g.write_double_attribute(result_name(P::snapshot, "axial_strain"), s.axial_strain);
    g.write_double_attribute(result_name(P::snapshot, "time_s"), s.time_s);
    write_named(g, result_name_spec(P::snapshot, "grain_position_m"), std::span<const eng::Vec3>(s.grain_position_m));
    write_named(g, result_name_spec(P::snapshot, "grain_radius_m"), std::span<const double>(s.grain_radius_m));
    write_named(g, result_name_spec(P::snapshot, "grain_velocity_m_per_s"), std::span<const eng::Vec3>(s.grain_velocity_m_per_s));
    write_named(g, result_name_spec(P::snapshot, "wire_node_position_m"), std::span<const eng::Vec3>(s.wire_node_position_m));
    write_named(g, result_name_spec(P::snapshot, "wire_segment_strain"), std::span<const double>(s.wire_segment_strain));
    write_named(g, result_name_spec(P::snapshot, "membrane_node_position_m"), std::span<const eng::Vec3>(s.membrane_node_position_m));
    std::vector<std::uint32_t> tri;
    tri.reserve(3 * s.membrane_triangles.size());
    for (const auto& t : s.membrane_triangles) tri.insert(tri.end(), t.begin(), t.end());
    write_named(g, result_name_spec(P::snapshot, "membrane_triangles"), std::span<const std::uint32_t>(tri), 3);

    const eng::ForceNetwork& f = s.forces;
    std::vector<std::uint32_t> pairs;
    pairs.reserve(4 * f.first.size());
    for (std::size_t i = 0; i < f.first.size(); ++i) {
        pairs.push_back(static_cast<std::uint32_t>(f.first[i].kind()));
        pairs.push_back(f.first[i].index());
        pairs.push_back(static_cast<std::uint32_t>(f.second[i].kind()));
        pairs.push_back(f.second[i].index());
    }
    write_named(g, result_name_spec(P::snapshot, "contact_bodies"), std::span<const std::uint32_t>(pairs), 4);
    write_named(g, result_name_spec(P::snapshot, "contact_force_n"), std::span<const eng::Vec3>(f.force_n));
    write_named(g, result_name_spec(P::snapshot, "contact_normal_force_n"), std::span<const double>(f.normal_force_n));
    std::vector<std::uint32_t> walls;
    walls.reserve(3 * f.wall.size());
    for (std::size_t i = 0; i < f.wall.size(); ++i) {
        walls.push_back(f.wall[i]);
        walls.push_back(static_cast<std::uint32_t>(f.wall_body[i].kind()));
        walls.push_back(f.wall_body[i].index());
    }
    write_named(g, result_name_spec(P::snapshot, "wall_contact_bodies"), std::span<const std::uint32_t>(walls), 3);
    write_named(g, result_name_spec(P::snapshot, "wall_contact_force_n"), std::span<const eng::Vec3>(f.wall_force_n));
}

eng::BodyRef body(std::uint32_t kind, std::uint32_t index)
{
    if (kind > static_cast<std::uint32_t>(eng::BodyKind::membrane) || index > eng::BodyRef::max_index)
        throw std::runtime_error("a contact names no body (kind " + std::to_string(kind) + ", index "
                                 + std::to_string(index) + ")");
    return {static_cast<eng::BodyKind>(kind), index};
}

eng::TriaxialSnapshot read_snapshot(const io::Group& g)
{
    eng::TriaxialSnapshot s;
    s.requested_axial_strain = g.read_double_attribute(result_name(P::snapshot, "requested_axial_strain"));
    s.axial_strain = g.read_double_attribute(result_name(P::snapshot, "axial_strain"));
    s.time_s = g.read_double_attribute(result_name(P::snapshot, "time_s"));
    s.grain_position_m = read_vec3s(g, result_name(P::snapshot, "grain_position_m"));
    s.grain_radius_m = read_doubles(g, result_name(P::snapshot, "grain_radius_m"));
    s.grain_velocity_m_per_s = read_vec3s(g, result_name(P::snapshot, "grain_velocity_m_per_s"));
    s.wire_node_position_m = read_vec3s(g, result_name(P::snapshot, "wire_node_position_m"));
    s.wire_segment_strain = read_doubles(g, result_name(P::snapshot, "wire_segment_strain"));
    s.membrane_node_position_m = read_vec3s(g, result_name(P::snapshot, "membrane_node_position_m"));
    const std::vector<std::uint32_t> tri = read_u32s(g, result_name(P::snapshot, "membrane_triangles"), 3);
    for (std::size_t i = 0; i + 2 < tri.size(); i += 3) s.membrane_triangles.push_back({tri[i], tri[i + 1], tri[i + 2]});

    eng::ForceNetwork& f = s.forces;
    const std::vector<std::uint32_t> pairs = read_u32s(g, result_name(P::snapshot, "contact_bodies"), 4);
    for (std::size_t i = 0; i + 3 < pairs.size(); i += 4) {
        f.first.push_back(body(pairs[i], pairs[i + 1]));
        f.second.push_back(body(pairs[i + 2], pairs[i + 3]));
    }
    f.force_n = read_vec3s(g, result_name(P::snapshot, "contact_force_n"));
    f.normal_force_n = read_doubles(g, result_name(P::snapshot, "contact_normal_force_n"));
    const std::vector<std::uint32_t> walls = read_u32s(g, result_name(P::snapshot, "wall_contact_bodies"), 3);
    for (std::size_t i = 0; i + 2 < walls.size(); i += 3) {
        f.wall.push_back(walls[i]);
        f.wall_body.push_back(body(walls[i + 1], walls[i + 2]));
    }
    f.wall_force_n = read_vec3s(g, result_name(P::snapshot, "wall_contact_force_n"));
    if (f.force_n.size() != f.first.size() || f.normal_force_n.size() != f.first.size()
        || f.wall_force_n.size() != f.wall.size())
        throw std::runtime_error(g.path() + ": the force network's arrays differ in length");
    return s;
}

void write_curve(io::Group& g, const CurveNames& n, const eng::analysis::CurveReading& c)
{
    g.write_string_attribute(n.shape, eng::analysis::to_string(c.shape));
    g.write_int_attribute(n.sample, static_cast<std::int64_t>(c.index));
    g.write_double_attribute(n.smoothed_maximum, c.value);
    g.write_double_attribute(n.smoothed_end, c.end_value);
    g.write_double_attribute(n.drop, c.drop);
    g.write_double_attribute(n.end_rise, c.end_rise);
}

eng::analysis::CurveShape read_shape(const io::Group& g, std::string_view name)
{
    const std::string text = g.read_string_attribute(name);
    for (auto shape : {eng::analysis::CurveShape::peak, eng::analysis::CurveShape::plateau, eng::analysis::CurveShape::rising})
        if (text == eng::analysis::to_string(shape)) return shape;
    throw std::runtime_error(g.path() + ": attribute " + std::string(name) + " is \"" + text + "\", not peak, plateau or rising");
}

std::size_t read_index(const io::Group& g, std::string_view name)
{
    const std::int64_t v = g.read_int_attribute(name);
    if (v < 0) throw std::runtime_error(g.path() + ": attribute " + std::string(name) + " is negative");
    return static_cast<std::size_t>(v);
}

eng::analysis::CurveReading read_curve(const io::Group& g, const CurveNames& n)
{
    eng::analysis::CurveReading c;
    c.shape = read_shape(g, n.shape);
    c.index = read_index(g, n.sample);
    c.value = g.read_double_attribute(n.smoothed_maximum);
    c.end_value = g.read_double_attribute(n.smoothed_end);
    c.drop = g.read_double_attribute(n.drop);
    c.end_rise = g.read_double_attribute(n.end_rise);
    return c;
}

/// A record's time series: its columns, then `phase` (meaning `phase_meaning`).
void write_series(io::Group& g, const eng::TriaxialSeries& s, std::string_view phase_meaning)
{
    for_each_series_column(s, [&](const SeriesColumnSpec& c, const auto& column) {
        units(g.write_dataset(c.name, std::span(column)), c.units);
    });
    std::vector<std::int32_t> phase(s.phase.begin(), s.phase.end());
    units(g.write_dataset(eng::series_column("phase").name, std::span<const std::int32_t>(phase)), phase_meaning);
}

/// What write_series wrote; a phase must lie in [0, last_phase].
eng::TriaxialSeries read_series(const io::Group& g, std::int64_t last_phase)
{
    eng::TriaxialSeries s;
    for_each_series_column(s, [&](const SeriesColumnSpec& c, auto& column) {
        using T = typename std::remove_cvref_t<decltype(column)>::value_type;
        if constexpr (std::is_same_v<T, double>) {
            column = read_doubles(g, c.name);
        } else {
            const io::Dataset d = g.open_dataset(c.name);
            column.clear();
            for (std::int64_t x : d.read_int64s()) {
                if (x < 0) throw std::runtime_error(d.path() + ": negative count");
                column.push_back(static_cast<T>(x));
            }
        }
    });
    const io::Dataset phase = g.open_dataset(eng::series_column("phase").name);
    for (std::int64_t p : phase.read_int64s()) {
        if (p < 0 || p > last_phase)
            throw std::runtime_error(phase.path() + ": a phase is not in 0.." + std::to_string(last_phase));
        s.phase.push_back(static_cast<std::uint8_t>(p));
    }
    const std::size_t rows = s.size();
    bool same_length = s.phase.size() == rows;
    for_each_series_column(s, [&](const SeriesColumnSpec& c, const auto& column) {
        // ε_v is derived when the test ends: empty in a running test's record.
        if (column.size() != rows && !(c.name == eng::series_column("volumetric_strain").name && column.empty()))
            same_length = false;
    });
    if (!same_length) throw std::runtime_error(g.path() + ": the time series differ in length");
    return s;
}

void write_snapshots(io::Group& g, const std::vector<eng::TriaxialSnapshot>& snapshots)
{
    io::Group snaps = g.create_group(result_name(P::record, "snapshots"));
    for (std::size_t i = 0; i < snapshots.size(); ++i)
        write_snapshot(snaps.create_group(std::string(result_name(P::snapshots, "snapshot_")) + std::to_string(i)), snapshots[i]);
}

std::vector<eng::TriaxialSnapshot> read_snapshots(const io::Group& g)
{
    std::vector<eng::TriaxialSnapshot> out;
    const io::Group snaps = g.open_group(result_name(P::record, "snapshots"));
    const std::vector<std::string> names = snaps.child_names();
    for (std::size_t i = 0; i < names.size(); ++i) {
        const std::string name = std::string(result_name(P::snapshots, "snapshot_")) + std::to_string(i);
        if (!snaps.exists(name)) throw std::runtime_error(snaps.path() + ": " + name + " is missing");
        out.push_back(read_snapshot(snaps.open_group(name)));
    }
    return out;
}

void write_profile(io::Group g, const eng::RadiusProfile& p)
{
    write_named(g, result_name_spec(P::profile, "height_m"), std::span<const double>(p.height_m));
    write_named(g, result_name_spec(P::profile, "radius_m"), std::span<const double>(p.radius_m));
    std::vector<std::int64_t> grains(p.grains.begin(), p.grains.end());
    write_named(g, result_name_spec(P::profile, "grains"), std::span<const std::int64_t>(grains));
}

eng::RadiusProfile read_profile(const io::Group& g)
{
    eng::RadiusProfile p;
    p.height_m = read_doubles(g, result_name(P::profile, "height_m"));
    p.radius_m = read_doubles(g, result_name(P::profile, "radius_m"));
    for (std::int64_t n : g.open_dataset(result_name(P::profile, "grains")).read_int64s()) p.grains.push_back(static_cast<std::uint32_t>(n));
    if (p.radius_m.size() != p.height_m.size() || p.grains.size() != p.height_m.size())
        throw std::runtime_error(g.path() + ": the profile's columns differ in length");
    return p;
}

/// The verdict, the times and the warnings of a record (eng::TriaxialResult,
/// eng::FreeStandingResult): the names a test's group and /free_standing share.
template <class Record>
void write_verdict_and_times(io::Group& g, const Record& r)
{
    g.write_int_attribute(result_name(P::record, "quasi_static"), r.verdict.quasi_static ? 1 : 0);
    g.write_double_attribute(result_name(P::record, "max_inertial_number"), r.verdict.max_inertial_number);
    g.write_double_attribute(result_name(P::record, "mean_kinetic_to_elastic"), r.verdict.mean_kinetic_to_elastic);
    g.write_double_attribute(result_name(P::record, "max_kinetic_to_elastic"), r.verdict.max_kinetic_to_elastic);
    g.write_string_attribute(result_name(P::record, "quasi_static_warning"), r.verdict.warning);
    g.write_int_attribute(result_name(P::record, "steps"), static_cast<std::int64_t>(r.steps));
    g.write_double_attribute(result_name(P::record, "time_step_s"), r.time_step_s);
    g.write_double_attribute(result_name(P::record, "simulated_time_s"), r.simulated_time_s);
    g.write_double_attribute(result_name(P::record, "wall_time_s"), r.wall_time_s);
    json::array warnings;
    for (const std::string& w : r.warnings) warnings.emplace_back(w);
    g.write_string_attribute(result_name(P::record, "warnings"), json::serialize(warnings));
}

/// What write_verdict_and_times wrote.
template <class Record>
void read_verdict_and_times(const io::Group& g, Record& r)
{
    r.verdict.quasi_static = g.read_int_attribute(result_name(P::record, "quasi_static")) != 0;
    r.verdict.max_inertial_number = g.read_double_attribute(result_name(P::record, "max_inertial_number"));
    r.verdict.mean_kinetic_to_elastic = g.read_double_attribute(result_name(P::record, "mean_kinetic_to_elastic"));
    r.verdict.max_kinetic_to_elastic = g.read_double_attribute(result_name(P::record, "max_kinetic_to_elastic"));
    r.verdict.warning = g.read_string_attribute(result_name(P::record, "quasi_static_warning"));
    const std::int64_t steps = g.read_int_attribute(result_name(P::record, "steps"));
    if (steps < 0) throw std::runtime_error(g.path() + ": negative step count");
    r.steps = static_cast<std::uint64_t>(steps);
    r.time_step_s = g.read_double_attribute(result_name(P::record, "time_step_s"));
    r.simulated_time_s = g.read_double_attribute(result_name(P::record, "simulated_time_s"));
    r.wall_time_s = g.read_double_attribute(result_name(P::record, "wall_time_s"));
    const json::value warnings = json::parse(g.read_string_attribute(result_name(P::record, "warnings")));
    for (const json::value& w : warnings.as_array()) r.warnings.emplace_back(w.as_string());
}

} // namespace

void write_wire_breaks(io::Group& g, const std::vector<eng::TestWireBreak>& breaks)
{
    if (breaks.empty()) return; // a whole wire: the files stay as they were
    io::Group b = g.create_group(result_name(P::record, "wire_breaks"));
    std::vector<std::int64_t> segment, cause;
    std::vector<double> time, test_time, strain, position, segment_strain, energy;
    for (const eng::TestWireBreak& e : breaks) {
        segment.push_back(e.event.segment);
        cause.push_back(static_cast<std::int64_t>(e.event.cause));
        time.push_back(e.event.time_s);
        test_time.push_back(e.test_time_s);
        strain.push_back(e.axial_strain);
        position.push_back(e.position_m);
        segment_strain.push_back(e.event.strain);
        energy.push_back(e.event.released_energy_j);
    }
    write_named(b, result_name_spec(P::wire_breaks, "segment"), std::span<const std::int64_t>(segment));
    write_named(b, result_name_spec(P::wire_breaks, "cause"), std::span<const std::int64_t>(cause));
    write_named(b, result_name_spec(P::wire_breaks, "time_s"), std::span<const double>(test_time));
    write_named(b, result_name_spec(P::wire_breaks, "world_time_s"), std::span<const double>(time));
    write_named(b, result_name_spec(P::wire_breaks, "axial_strain"), std::span<const double>(strain));
    write_named(b, result_name_spec(P::wire_breaks, "position_m"), std::span<const double>(position));
    write_named(b, result_name_spec(P::wire_breaks, "segment_strain"), std::span<const double>(segment_strain));
    write_named(b, result_name_spec(P::wire_breaks, "released_energy_j"), std::span<const double>(energy));
}

std::vector<eng::TestWireBreak> read_wire_breaks(const io::Group& g)
{
    std::vector<eng::TestWireBreak> out;
    if (!g.exists(result_name(P::record, "wire_breaks"))) return out;
    const io::Group b = g.open_group(result_name(P::record, "wire_breaks"));
    const std::vector<std::int64_t> segment = b.open_dataset(result_name(P::wire_breaks, "segment")).read_int64s();
    const std::vector<std::int64_t> cause = b.open_dataset(result_name(P::wire_breaks, "cause")).read_int64s();
    const std::vector<double> test_time = read_doubles(b, result_name(P::wire_breaks, "time_s")), time = read_doubles(b, result_name(P::wire_breaks, "world_time_s")),
                              strain = read_doubles(b, result_name(P::wire_breaks, "axial_strain")), position = read_doubles(b, result_name(P::wire_breaks, "position_m")),
                              segment_strain = read_doubles(b, result_name(P::wire_breaks, "segment_strain")), energy = read_doubles(b, result_name(P::wire_breaks, "released_energy_j"));
    const std::size_t n = segment.size();
    if (cause.size() != n || test_time.size() != n || time.size() != n || strain.size() != n || position.size() != n
        || segment_strain.size() != n || energy.size() != n)
        throw std::runtime_error(b.path() + ": the columns differ in length");
    for (std::size_t i = 0; i < n; ++i) {
        if (segment[i] < 0 || segment[i] > static_cast<std::int64_t>(UINT32_MAX) || cause[i] < 0 || cause[i] > 1)
            throw std::runtime_error(b.path() + ": a segment or cause is out of range");
        eng::TestWireBreak e;
        e.event = {.segment = static_cast<std::uint32_t>(segment[i]), .cause = static_cast<eng::WireBreakCause>(cause[i]),
            .time_s = time[i], .strain = segment_strain[i], .released_energy_j = energy[i]};
        e.test_time_s = test_time[i];
        e.axial_strain = strain[i];
        e.position_m = position[i];
        out.push_back(e);
    }
    return out;
}

void write_triaxial_result(io::Group& g, const eng::TriaxialResult& r)
{
    g.write_double_attribute(result_name(P::test, "peak_deviatoric_stress_pa"), r.peak_deviatoric_stress_pa);
    g.write_double_attribute(result_name(P::test, "peak_axial_strain"), r.peak_axial_strain);
    g.write_double_attribute(result_name(P::test, "peak_sigma1_pa"), r.peak_sigma1_pa);
    g.write_double_attribute(result_name(P::test, "peak_sigma3_effective_pa"), r.peak_sigma3_effective_pa);
    g.write_int_attribute(result_name(P::test, "peak_sample"), static_cast<std::int64_t>(r.peak_sample));
    if (r.strength) {
        const eng::analysis::StrengthReading& y = *r.strength;
        write_curve(g, yield_curve, y.stress_ratio);
        write_curve(g, max_q_curve, y.deviatoric);
        g.write_double_attribute(result_name(P::test, "yield_stress_ratio"), y.stress_ratio.value);
        g.write_double_attribute(result_name(P::test, "yield_axial_strain"), y.yield_axial_strain);
        g.write_double_attribute(result_name(P::test, "yield_sigma1_pa"), y.yield_sigma1_pa);
        g.write_double_attribute(result_name(P::test, "yield_sigma3_effective_pa"), y.yield_sigma3_pa);
        g.write_double_attribute(result_name(P::test, "residual_stress_ratio"), y.residual_stress_ratio);
    }
    g.write_double_attribute(result_name(P::test, "hold_time_s"), r.hold_time_s);
    g.write_double_attribute(result_name(P::test, "consolidated_sigma1_pa"), r.consolidated_sigma1_pa);
    if (r.consolidation) {
        g.write_string_attribute(result_name(P::test, "consolidation"), eng::to_string(*r.consolidation));
        g.write_double_attribute(result_name(P::test, "consolidation_target_pa"), r.consolidation_target_pa);
    }
    g.write_double_attribute(result_name(P::test, "initial_height_m"), r.initial_height_m);
    g.write_double_attribute(result_name(P::test, "initial_volume_m3"), r.initial_volume_m3);
    write_verdict_and_times(g, r);

    write_series(g, r.series, eng::triaxial_phase_units);
    write_snapshots(g, r.snapshots);
    write_wire_breaks(g, r.wire_breaks);
}

eng::TriaxialResult read_triaxial_result(const io::Group& g, Snapshots snapshots)
{
    eng::TriaxialResult r;
    r.peak_deviatoric_stress_pa = g.read_double_attribute(result_name(P::test, "peak_deviatoric_stress_pa"));
    r.peak_axial_strain = g.read_double_attribute(result_name(P::test, "peak_axial_strain"));
    r.peak_sigma1_pa = g.read_double_attribute(result_name(P::test, "peak_sigma1_pa"));
    r.peak_sigma3_effective_pa = g.read_double_attribute(result_name(P::test, "peak_sigma3_effective_pa"));
    r.peak_sample = read_index(g, result_name(P::test, "peak_sample"));
    if (g.has_attribute(result_name(P::test, "yield_shape"))) {
        eng::analysis::StrengthReading y;
        y.stress_ratio = read_curve(g, yield_curve);
        y.deviatoric = read_curve(g, max_q_curve);
        y.yield_axial_strain = g.read_double_attribute(result_name(P::test, "yield_axial_strain"));
        y.yield_sigma1_pa = g.read_double_attribute(result_name(P::test, "yield_sigma1_pa"));
        y.yield_sigma3_pa = g.read_double_attribute(result_name(P::test, "yield_sigma3_effective_pa"));
        y.residual_stress_ratio = g.read_double_attribute(result_name(P::test, "residual_stress_ratio"));
        r.strength = y;
    }
    r.hold_time_s = g.read_double_attribute(result_name(P::test, "hold_time_s"));
    r.consolidated_sigma1_pa = g.read_double_attribute(result_name(P::test, "consolidated_sigma1_pa"));
    if (g.has_attribute(result_name(P::test, "consolidation"))) { // absent in a file written before it was recorded
        const std::string c = g.read_string_attribute(result_name(P::test, "consolidation"));
        r.consolidation = eng::consolidation_from_string(c);
        if (!r.consolidation) throw std::runtime_error(g.path() + ": consolidation \"" + c + "\" is not cell_pressure or effective");
        r.consolidation_target_pa = g.read_double_attribute(result_name(P::test, "consolidation_target_pa"));
    }
    r.initial_height_m = g.read_double_attribute(result_name(P::test, "initial_height_m"));
    r.initial_volume_m3 = g.read_double_attribute(result_name(P::test, "initial_volume_m3"));
    read_verdict_and_times(g, r);

    r.series = read_series(g, static_cast<std::int64_t>(eng::TriaxialPhase::loading));
    const std::size_t rows = r.series.size();
    if (rows > 0 && r.peak_sample >= rows) throw std::runtime_error(g.path() + ": peak_sample is past the series");
    r.wire_breaks = read_wire_breaks(g);

    if (snapshots == Snapshots::skip) return r;
    r.snapshots = read_snapshots(g);
    return r;
}

double wire_length_per_volume_m_per_m3(const eng::PreparationReport& r)
{
    return r.sample_volume_m3 > 0.0 ? r.wire_length_m / r.sample_volume_m3 : std::numeric_limits<double>::quiet_NaN();
}

namespace {

/// The pull-out's figures as attributes pull_out_* of the test's group, its
/// rows in the group pull_out (api::pull_out_group), one per series row of
/// the phase.
void write_pull_out(io::Group& g, const eng::PullOutReading& p)
{
    g.write_string_attribute(result_name(P::free_standing, "pull_out_end"), eng::to_string(p.end));
    g.write_int_attribute(result_name(P::free_standing, "pull_out_node"), p.pulled_node);
    g.write_double_attribute(result_name(P::free_standing, "pull_out_peak_force_n"), p.peak_pull_force_n);
    g.write_double_attribute(result_name(P::free_standing, "pull_out_length_at_peak_m"), p.pulled_length_at_peak_m);
    g.write_double_attribute(result_name(P::free_standing, "pull_out_length_m"), p.pulled_length_m);
    g.write_double_attribute(result_name(P::free_standing, "pull_out_wire_in_column_before_m"), p.wire_in_column_before_m);
    g.write_double_attribute(result_name(P::free_standing, "pull_out_wire_in_column_m"), p.wire_in_column_m);
    g.write_int_attribute(result_name(P::free_standing, "pull_out_grains_in_column"), static_cast<std::int64_t>(p.grains_in_column));
    g.write_int_attribute(result_name(P::free_standing, "pull_out_wire_broke"), p.wire_broke ? 1 : 0);
    g.write_double_attribute(result_name(P::free_standing, "pull_out_ramp_inertia_n"), p.ramp_inertia_n);
    io::Group s = g.create_group(std::string(api::pull_out_group));
    const eng::PullOutSeries& x = p.series;
    write_named(s, result_name_spec(P::pull_out, "time_s"), std::span<const double>(x.time_s));
    write_named(s, result_name_spec(P::pull_out, "pulled_length_m"), std::span<const double>(x.pulled_length_m));
    write_named(s, result_name_spec(P::pull_out, "pull_force_n"), std::span<const double>(x.pull_force_n));
    write_named(s, result_name_spec(P::pull_out, "end_tension_n"), std::span<const double>(x.end_tension_n));
    write_named(s, result_name_spec(P::pull_out, "wire_in_column_m"), std::span<const double>(x.wire_in_column_m));
    write_named(s, result_name_spec(P::pull_out, "grains_in_column"), std::span<const double>(x.grains_in_column));
}

eng::PullOutReading read_pull_out(const io::Group& g)
{
    eng::PullOutReading p;
    const std::string end = g.read_string_attribute(result_name(P::free_standing, "pull_out_end"));
    bool known = false;
    for (auto e : {eng::PullOutEnd::length, eng::PullOutEnd::wire_out, eng::PullOutEnd::time, eng::PullOutEnd::host})
        if (end == eng::to_string(e)) {
            p.end = e;
            known = true;
        }
    if (!known) throw std::runtime_error(g.path() + ": pull_out_end \"" + end + "\" is not a known end");
    p.pulled_node = static_cast<std::uint32_t>(read_index(g, result_name(P::free_standing, "pull_out_node")));
    p.peak_pull_force_n = g.read_double_attribute(result_name(P::free_standing, "pull_out_peak_force_n"));
    p.pulled_length_at_peak_m = g.read_double_attribute(result_name(P::free_standing, "pull_out_length_at_peak_m"));
    p.pulled_length_m = g.read_double_attribute(result_name(P::free_standing, "pull_out_length_m"));
    p.wire_in_column_before_m = g.read_double_attribute(result_name(P::free_standing, "pull_out_wire_in_column_before_m"));
    p.wire_in_column_m = g.read_double_attribute(result_name(P::free_standing, "pull_out_wire_in_column_m"));
    p.grains_in_column = read_index(g, result_name(P::free_standing, "pull_out_grains_in_column"));
    p.wire_broke = g.read_int_attribute(result_name(P::free_standing, "pull_out_wire_broke")) != 0;
    p.ramp_inertia_n = g.read_double_attribute(result_name(P::free_standing, "pull_out_ramp_inertia_n"));
    const io::Group s = g.open_group(std::string(api::pull_out_group));
    eng::PullOutSeries& x = p.series;
    x.time_s = read_doubles(s, result_name(P::pull_out, "time_s"));
    x.pulled_length_m = read_doubles(s, result_name(P::pull_out, "pulled_length_m"));
    x.pull_force_n = read_doubles(s, result_name(P::pull_out, "pull_force_n"));
    x.end_tension_n = read_doubles(s, result_name(P::pull_out, "end_tension_n"));
    x.wire_in_column_m = read_doubles(s, result_name(P::pull_out, "wire_in_column_m"));
    x.grains_in_column = read_doubles(s, result_name(P::pull_out, "grains_in_column"));
    const std::size_t n = x.size();
    if (x.pulled_length_m.size() != n || x.pull_force_n.size() != n || x.end_tension_n.size() != n
        || x.wire_in_column_m.size() != n || x.grains_in_column.size() != n)
        throw std::runtime_error(s.path() + ": the pull-out's columns differ in length");
    return p;
}

} // namespace

void write_free_standing_result(io::Group& g, const eng::FreeStandingResult& r)
{
    const eng::SettlingReading& s = r.settling;
    g.write_int_attribute(result_name(P::free_standing, "at_rest"), s.at_rest ? 1 : 0);
    g.write_double_attribute(result_name(P::free_standing, "time_to_rest_s"), s.time_to_rest_s);
    g.write_double_attribute(result_name(P::free_standing, "height_before_m"), s.height_before_m);
    g.write_double_attribute(result_name(P::free_standing, "height_m"), s.height_m);
    g.write_double_attribute(result_name(P::free_standing, "height_loss"), s.height_loss);
    g.write_double_attribute(result_name(P::free_standing, "radius_before_m"), s.radius_before_m);
    g.write_double_attribute(result_name(P::free_standing, "radius_m"), s.radius_m);
    g.write_int_attribute(result_name(P::free_standing, "escaped_grains"), static_cast<std::int64_t>(s.escaped_grains));
    g.write_double_attribute(result_name(P::free_standing, "bulk_height_before_m"), s.bulk_height_before_m);
    g.write_double_attribute(result_name(P::free_standing, "bulk_height_m"), s.bulk_height_m);
    g.write_double_attribute(result_name(P::free_standing, "bulk_height_loss"), s.bulk_height_loss);
    g.write_int_attribute(result_name(P::free_standing, "grains"), static_cast<std::int64_t>(s.grains));
    g.write_double_attribute(result_name(P::free_standing, "lost_fraction"), s.lost_fraction);
    g.write_double_attribute(result_name(P::free_standing, "weight_n"), s.weight_n);
    g.write_double_attribute(result_name(P::free_standing, "base_force_n"), s.base_force_n);
    g.write_double_attribute(result_name(P::free_standing, "base_force_tolerance_n"), s.base_force_tolerance_n);
    g.write_int_attribute(result_name(P::free_standing, "stands"), s.stands ? 1 : 0);
    g.write_double_attribute(result_name(P::free_standing, "max_removal_kinetic_energy_j"), s.max_removal_kinetic_energy_j);
    write_profile(g.create_group(std::string(api::free_standing_profiles[0])), s.profile_before);
    write_profile(g.create_group(std::string(api::free_standing_profiles[1])), s.profile);
    if (r.dead_load) {
        const eng::DeadLoadReading& d = *r.dead_load;
        g.write_double_attribute(result_name(P::free_standing, "dead_load_n"), d.force_n);
        g.write_double_attribute(result_name(P::free_standing, "dead_load_stress_pa"), d.stress_pa);
        g.write_double_attribute(result_name(P::free_standing, "dead_load_strain_at_load"), d.strain_at_load);
        g.write_double_attribute(result_name(P::free_standing, "dead_load_strain_at_end"), d.strain_at_end);
        g.write_double_attribute(result_name(P::free_standing, "dead_load_creep_strain"), d.creep_strain);
        g.write_int_attribute(result_name(P::free_standing, "dead_load_holds"), d.holds ? 1 : 0);
    }
    if (r.compression) {
        const eng::CompressionReading& c = *r.compression;
        write_curve(g, strength_curve, c.strength);
        g.write_double_attribute(result_name(P::free_standing, "strength_axial_strain"), c.strength_axial_strain);
        g.write_double_attribute(result_name(P::free_standing, "max_sigma1_pa"), c.max_sigma1_pa);
        g.write_int_attribute(result_name(P::free_standing, "max_sigma1_sample"), static_cast<std::int64_t>(c.max_sigma1_sample));
        g.write_int_attribute(result_name(P::free_standing, "failed"), c.failed ? 1 : 0);
        if (c.failure_mode) {
            g.write_string_attribute(result_name(P::free_standing, "failure_mode"), eng::to_string(*c.failure_mode));
            g.write_double_attribute(result_name(P::free_standing, "spilled_fraction"), c.spilled_fraction);
            g.write_double_attribute(result_name(P::free_standing, "bulge_m"), c.bulge_m);
        }
        write_profile(g.create_group(std::string(api::free_standing_profiles[2])), c.profile_at_peak);
        write_profile(g.create_group(std::string(api::free_standing_profiles[3])), c.profile_at_end);
        write_named(g, result_name_spec(P::free_standing, "wire_strain_at_peak"), std::span<const double>(c.wire_strain_at_peak));
        write_named(g, result_name_spec(P::free_standing, "wire_tension_at_peak_n"), std::span<const double>(c.wire_tension_at_peak_n));
    }
    g.write_int_attribute(result_name(P::free_standing, "loading_start_sample"), static_cast<std::int64_t>(r.loading_start_sample));
    write_verdict_and_times(g, r);
    if (r.pull_out) write_pull_out(g, *r.pull_out);
    write_series(g, r.series, r.pull_out ? eng::free_standing_pull_out_phase_units : eng::free_standing_phase_units);
    write_snapshots(g, r.snapshots);
    write_wire_breaks(g, r.wire_breaks);
    if (r.peak_snapshot) write_snapshot(g.create_group(std::string(api::free_standing_peak_snapshot)), *r.peak_snapshot);
}

eng::FreeStandingResult read_free_standing_result(const io::Group& g)
{
    eng::FreeStandingResult r;
    eng::SettlingReading& s = r.settling;
    s.at_rest = g.read_int_attribute(result_name(P::free_standing, "at_rest")) != 0;
    s.time_to_rest_s = g.read_double_attribute(result_name(P::free_standing, "time_to_rest_s"));
    s.height_before_m = g.read_double_attribute(result_name(P::free_standing, "height_before_m"));
    s.height_m = g.read_double_attribute(result_name(P::free_standing, "height_m"));
    s.height_loss = g.read_double_attribute(result_name(P::free_standing, "height_loss"));
    s.radius_before_m = g.read_double_attribute(result_name(P::free_standing, "radius_before_m"));
    s.radius_m = g.read_double_attribute(result_name(P::free_standing, "radius_m"));
    s.escaped_grains = read_index(g, result_name(P::free_standing, "escaped_grains"));
    if (g.has_attribute(result_name(P::free_standing, "bulk_height_m"))) { // written since 2026-12-06: an older file's verdict read the top
        s.bulk_height_before_m = g.read_double_attribute(result_name(P::free_standing, "bulk_height_before_m"));
        s.bulk_height_m = g.read_double_attribute(result_name(P::free_standing, "bulk_height_m"));
        s.bulk_height_loss = g.read_double_attribute(result_name(P::free_standing, "bulk_height_loss"));
        s.grains = read_index(g, result_name(P::free_standing, "grains"));
        s.lost_fraction = g.read_double_attribute(result_name(P::free_standing, "lost_fraction"));
    } else {
        s.bulk_height_before_m = s.bulk_height_m = s.bulk_height_loss = s.lost_fraction
            = std::numeric_limits<double>::quiet_NaN();
    }
    s.weight_n = g.read_double_attribute(result_name(P::free_standing, "weight_n"));
    s.base_force_n = g.read_double_attribute(result_name(P::free_standing, "base_force_n"));
    s.base_force_tolerance_n = g.read_double_attribute(result_name(P::free_standing, "base_force_tolerance_n"));
    s.stands = g.read_int_attribute(result_name(P::free_standing, "stands")) != 0;
    s.max_removal_kinetic_energy_j = g.read_double_attribute(result_name(P::free_standing, "max_removal_kinetic_energy_j"));
    s.profile_before = read_profile(g.open_group(std::string(api::free_standing_profiles[0])));
    s.profile = read_profile(g.open_group(std::string(api::free_standing_profiles[1])));
    if (g.has_attribute(result_name(P::free_standing, "dead_load_n"))) {
        eng::DeadLoadReading d;
        d.force_n = g.read_double_attribute(result_name(P::free_standing, "dead_load_n"));
        d.stress_pa = g.read_double_attribute(result_name(P::free_standing, "dead_load_stress_pa"));
        d.strain_at_load = g.read_double_attribute(result_name(P::free_standing, "dead_load_strain_at_load"));
        d.strain_at_end = g.read_double_attribute(result_name(P::free_standing, "dead_load_strain_at_end"));
        d.creep_strain = g.read_double_attribute(result_name(P::free_standing, "dead_load_creep_strain"));
        d.holds = g.read_int_attribute(result_name(P::free_standing, "dead_load_holds")) != 0;
        r.dead_load = d;
    }
    if (g.has_attribute(result_name(P::free_standing, "strength_shape"))) {
        eng::CompressionReading c;
        c.strength = read_curve(g, strength_curve);
        c.strength_axial_strain = g.read_double_attribute(result_name(P::free_standing, "strength_axial_strain"));
        c.max_sigma1_pa = g.read_double_attribute(result_name(P::free_standing, "max_sigma1_pa"));
        c.max_sigma1_sample = read_index(g, result_name(P::free_standing, "max_sigma1_sample"));
        c.failed = g.read_int_attribute(result_name(P::free_standing, "failed")) != 0;
        if (g.has_attribute(result_name(P::free_standing, "failure_mode"))) { // written since 2026-12-06
            const std::string mode = g.read_string_attribute(result_name(P::free_standing, "failure_mode"));
            for (auto m : {eng::FailureMode::wire_break, eng::FailureMode::grains_spilling, eng::FailureMode::bulging,
                     eng::FailureMode::unresolved})
                if (mode == eng::to_string(m)) c.failure_mode = m;
            if (!c.failure_mode) throw std::runtime_error(g.path() + ": failure_mode \"" + mode + "\" is not a failure mode");
            c.spilled_fraction = g.read_double_attribute(result_name(P::free_standing, "spilled_fraction"));
            c.bulge_m = g.read_double_attribute(result_name(P::free_standing, "bulge_m"));
        } else {
            c.spilled_fraction = c.bulge_m = std::numeric_limits<double>::quiet_NaN();
        }
        c.profile_at_peak = read_profile(g.open_group(std::string(api::free_standing_profiles[2])));
        c.profile_at_end = read_profile(g.open_group(std::string(api::free_standing_profiles[3])));
        c.wire_strain_at_peak = read_doubles(g, std::string(api::free_standing_wire_arrays[0]));
        c.wire_tension_at_peak_n = read_doubles(g, std::string(api::free_standing_wire_arrays[1]));
        r.compression = std::move(c);
    }
    r.loading_start_sample = read_index(g, result_name(P::free_standing, "loading_start_sample"));
    read_verdict_and_times(g, r);
    r.series = read_series(g, static_cast<std::int64_t>(eng::FreeStandingPhase::pull_out));
    r.wire_breaks = read_wire_breaks(g);
    if (g.has_attribute(result_name(P::free_standing, "pull_out_end"))) r.pull_out = read_pull_out(g);
    const std::size_t rows = r.series.size();
    // A running test's record (a checkpoint's) may not have the first row of
    // its loading or pull-out yet, nor any row: loading_start_sample = rows.
    if (r.loading_start_sample > rows || (r.compression && r.compression->strength.index >= rows))
        throw std::runtime_error(g.path() + ": a row index is past the series");
    r.snapshots = read_snapshots(g);
    if (const std::string peak(api::free_standing_peak_snapshot); g.exists(peak)) r.peak_snapshot = read_snapshot(g.open_group(peak));
    return r;
}

std::vector<api::SeriesColumn> series_columns(const eng::TriaxialSeries& s)
{
    std::vector<api::SeriesColumn> out;
    const std::size_t rows = s.size();
    for_each_series_column(s, [&](const SeriesColumnSpec& c, const auto& column) {
        if (column.size() != rows) return;  // ε_v of a running test
        out.push_back({std::string(c.name), std::string(c.units), std::vector<double>(column.begin(), column.end())});
    });
    const SeriesColumnSpec& phase = eng::series_column("phase");
    out.push_back({std::string(phase.name), std::string(phase.units), std::vector<double>(s.phase.begin(), s.phase.end())});
    return out;
}

TestSoFar read_test_so_far(const JobDir& dir, std::size_t k, Snapshots snapshots)
{
    // The runner writes test_K.h5, then removes the checkpoint: look for the
    // finished file first, and again when the checkpoint went in between.
    const auto finished = [&]() -> std::optional<TestSoFar> {
        std::error_code ec;
        if (!std::filesystem::exists(dir.test(k), ec)) return std::nullopt;
        const io::File f = io::File::open_read_only(dir.test(k));
        return TestSoFar{TestSoFar::State::finished, read_triaxial_result(f.root().open_group(test_file_group), snapshots)};
    };
    if (auto done = finished()) return std::move(*done);
    std::error_code ec;
    if (std::filesystem::exists(dir.checkpoint(k), ec)) {
        try {
            // The driver's state only; the World beside it is not read.
            const io::File f = io::File::open_read_only(dir.checkpoint(k));
            return {TestSoFar::State::running,
                read_driver_state(f.root().open_group(eng::snapshot_host_group), snapshots).result};
        } catch (const io::Hdf5Error&) {
            if (std::filesystem::exists(dir.checkpoint(k), ec)) throw;
        }
    }
    if (auto done = finished()) return std::move(*done);
    return {};
}

std::string_view to_string(TestSoFar::State s)
{
    switch (s) {
    case TestSoFar::State::waiting: return "waiting";
    case TestSoFar::State::running: return "running";
    case TestSoFar::State::finished: return "finished";
    }
    return "?";
}

namespace {

/// The names in a checkpoint's driver state (the snapshot's host group, written
/// by write_driver_state, write_cuboid_driver_state,
/// write_free_standing_driver_state and write_preparation_state, read by their
/// readers): each name once, for the writer and the reader.
namespace state_name {
// Every test's and the preparation's
constexpr std::string_view steps = "steps";
constexpr std::string_view phase = "phase";
constexpr std::string_view wall_time_s = "wall_time_s";
// Every test's: 1 when the live springs' warning is in the result's warnings
constexpr std::string_view live_springs_reported = "live_springs_reported";
// The tests' (membrane and cuboid cell, free-standing)
constexpr std::string_view reference_height_m = "reference_height_m";
constexpr std::string_view last_sample_step = "last_sample_step";
constexpr std::string_view next_snapshot = "next_snapshot";
constexpr std::string_view window_force_n = "window_force_n";
constexpr std::string_view result = "result";
// The membrane cell's test (TriaxialDriverState; the cuboid cell's too)
constexpr std::string_view expected_steps = "expected_steps";
constexpr std::string_view loading = "loading";
constexpr std::string_view loading_start_sample = "loading_start_sample";
constexpr std::string_view loading_start_step = "loading_start_step";
constexpr std::string_view progress_at_loading = "progress_at_loading";
constexpr std::string_view window_filled = "window_filled";
constexpr std::string_view has_window_sigma1 = "has_window_sigma1";
constexpr std::string_view window_sigma1_pa = "window_sigma1_pa";
constexpr std::string_view column_radius_m = "column_radius_m";
constexpr std::string_view cap_nodes = "cap_nodes";
// The cuboid cell's box: a group of rows
constexpr std::string_view box = "box";
constexpr std::string_view width_x_m = "width_x_m";
constexpr std::string_view width_y_m = "width_y_m";
constexpr std::string_view sigma_x_pa = "sigma_x_pa";
constexpr std::string_view sigma_y_pa = "sigma_y_pa";
// The free-standing test's (FreeStandingDriverState)
constexpr std::string_view phase_start_step = "phase_start_step";
constexpr std::string_view reference_radius_m = "reference_radius_m";
constexpr std::string_view max_sigma1_pa = "max_sigma1_pa";
constexpr std::string_view profile_at_max_sigma1 = "profile_at_max_sigma1";
constexpr std::string_view max_window_sigma1_pa = "max_window_sigma1_pa";
constexpr std::string_view below_since_strain = "below_since_strain";
constexpr std::string_view loading_begun = "loading_begun";
constexpr std::string_view window_kinetic_energy_j = "window_kinetic_energy_j";
constexpr std::string_view pull_force_sum_n = "pull_force_sum_n";
constexpr std::string_view end_tension_sum_n = "end_tension_sum_n";
constexpr std::string_view pull_steps_summed = "pull_steps_summed";
constexpr std::array<std::string_view, 3> pull_start_m{"pull_start_m_x", "pull_start_m_y", "pull_start_m_z"};
// The preparation's (PreparationDriverState)
constexpr std::string_view rng_state = "rng_state";
constexpr std::string_view owed_grains = "owed_grains";
constexpr std::string_view next_batch_s = "next_batch_s";
constexpr std::string_view poured_volume_m3 = "poured_volume_m3";
constexpr std::string_view pile_top_m = "pile_top_m";
constexpr std::string_view nozzle_target_m = "nozzle_target_m";
constexpr std::string_view laid_all = "laid_all";
constexpr std::string_view nozzle_z_m = "nozzle_z_m";
constexpr std::string_view nozzle_path_m = "nozzle_path_m";
constexpr std::string_view nozzle_last_node_path_m = "nozzle_last_node_path_m";
constexpr std::string_view nozzle_integration_s_m = "nozzle_integration_s_m";
constexpr std::string_view nozzle_integration_theta_rad = "nozzle_integration_theta_rad";
constexpr std::string_view settled_before_lid = "settled_before_lid";
constexpr std::string_view settled_under_lid = "settled_under_lid";
constexpr std::string_view top_plate_wall = "top_plate_wall";
} // namespace state_name

/// Whether the live springs' warning is in `warnings`, from the driver state
/// in `g`: its flag, or in a checkpoint written before the flag
/// (2026-12-07), the warning's own words.
bool read_live_springs_reported(const io::Group& g, const std::vector<std::string>& warnings)
{
    if (g.has_attribute(state_name::live_springs_reported))
        return g.read_int_attribute(state_name::live_springs_reported) != 0;
    return std::any_of(warnings.begin(), warnings.end(),
        [](const std::string& w) { return w.find(eng::live_spring_warning_marker) != std::string::npos; });
}

} // namespace

void write_driver_state(io::Group& g, const eng::TriaxialDriverState& s)
{
    g.write_int_attribute(state_name::steps, static_cast<std::int64_t>(s.steps));
    g.write_int_attribute(state_name::expected_steps, static_cast<std::int64_t>(s.expected_steps));
    g.write_int_attribute(state_name::loading, s.loading ? 1 : 0);
    g.write_double_attribute(state_name::reference_height_m, s.reference_height_m);
    // "none yet" (the largest value) is written as -1: the same bits.
    g.write_int_attribute(state_name::last_sample_step, static_cast<std::int64_t>(s.last_sample_step));
    g.write_int_attribute(state_name::next_snapshot, static_cast<std::int64_t>(s.next_snapshot));
    g.write_int_attribute(state_name::loading_start_sample, static_cast<std::int64_t>(s.loading_start_sample));
    g.write_int_attribute(state_name::loading_start_step, static_cast<std::int64_t>(s.loading_start_step));
    g.write_double_attribute(state_name::progress_at_loading, s.progress_at_loading);
    g.write_double_attribute(state_name::window_force_n, s.window_force_n);
    g.write_int_attribute(state_name::window_filled, static_cast<std::int64_t>(s.window_filled));
    g.write_int_attribute(state_name::has_window_sigma1, s.window_sigma1_pa ? 1 : 0);
    g.write_double_attribute(state_name::window_sigma1_pa, s.window_sigma1_pa.value_or(0.0));
    g.write_double_attribute(state_name::column_radius_m, s.column_radius_m);
    g.write_double_attribute(state_name::wall_time_s, s.wall_time_s);
    g.write_dataset(state_name::cap_nodes, std::span<const std::uint32_t>(s.cap_nodes));
    g.write_int_attribute(state_name::live_springs_reported, s.live_springs_reported ? 1 : 0);
    io::Group result = g.create_group(state_name::result);
    write_triaxial_result(result, s.result);
}

eng::TriaxialDriverState read_driver_state(const io::Group& g, Snapshots snapshots)
{
    eng::TriaxialDriverState s;
    s.steps = read_index(g, state_name::steps);
    s.expected_steps = read_index(g, state_name::expected_steps);
    s.loading = g.read_int_attribute(state_name::loading) != 0;
    s.reference_height_m = g.read_double_attribute(state_name::reference_height_m);
    s.last_sample_step = static_cast<std::uint64_t>(g.read_int_attribute(state_name::last_sample_step));
    s.next_snapshot = read_index(g, state_name::next_snapshot);
    s.loading_start_sample = read_index(g, state_name::loading_start_sample);
    // Absent in a checkpoint written before them: steps as they are.
    if (g.has_attribute(state_name::loading_start_step)) {
        s.loading_start_step = read_index(g, state_name::loading_start_step);
        s.progress_at_loading = g.read_double_attribute(state_name::progress_at_loading);
        if (!(s.progress_at_loading >= 0.0 && s.progress_at_loading <= 1.0))
            throw std::runtime_error(g.path() + ": progress_at_loading out of [0, 1]");
    }
    s.window_force_n = g.read_double_attribute(state_name::window_force_n);
    s.window_filled = read_index(g, state_name::window_filled);
    if (g.read_int_attribute(state_name::has_window_sigma1) != 0)
        s.window_sigma1_pa = g.read_double_attribute(state_name::window_sigma1_pa);
    s.column_radius_m = g.read_double_attribute(state_name::column_radius_m);
    s.wall_time_s = g.read_double_attribute(state_name::wall_time_s);
    s.cap_nodes = read_u32s(g, state_name::cap_nodes, 1);
    s.result = read_triaxial_result(g.open_group(state_name::result), snapshots);
    s.live_springs_reported = read_live_springs_reported(g, s.result.warnings);
    return s;
}

void write_cuboid_driver_state(io::Group& g, const eng::CuboidDriverState& s)
{
    write_driver_state(g, s.triaxial);
    io::Group box = g.create_group(state_name::box);
    units(box.write_dataset(state_name::width_x_m, std::span<const double>(s.width_x_m)), "m");
    units(box.write_dataset(state_name::width_y_m, std::span<const double>(s.width_y_m)), "m");
    units(box.write_dataset(state_name::sigma_x_pa, std::span<const double>(s.sigma_x_pa)), "Pa");
    units(box.write_dataset(state_name::sigma_y_pa, std::span<const double>(s.sigma_y_pa)), "Pa");
}

eng::CuboidDriverState read_cuboid_driver_state(const io::Group& g)
{
    eng::CuboidDriverState s;
    s.triaxial = read_driver_state(g);
    const io::Group box = g.open_group(state_name::box);
    s.width_x_m = read_doubles(box, state_name::width_x_m);
    s.width_y_m = read_doubles(box, state_name::width_y_m);
    s.sigma_x_pa = read_doubles(box, state_name::sigma_x_pa);
    s.sigma_y_pa = read_doubles(box, state_name::sigma_y_pa);
    return s;
}

void write_free_standing_driver_state(io::Group& g, const eng::FreeStandingDriverState& s)
{
    g.write_int_attribute(state_name::steps, static_cast<std::int64_t>(s.steps));
    g.write_string_attribute(state_name::phase, eng::to_string(s.phase));
    g.write_int_attribute(state_name::phase_start_step, static_cast<std::int64_t>(s.phase_start_step));
    g.write_double_attribute(state_name::reference_height_m, s.reference_height_m);
    g.write_double_attribute(state_name::reference_radius_m, s.reference_radius_m);
    // "none yet" (the largest value) is written as -1: the same bits.
    g.write_int_attribute(state_name::last_sample_step, static_cast<std::int64_t>(s.last_sample_step));
    g.write_int_attribute(state_name::next_snapshot, static_cast<std::int64_t>(s.next_snapshot));
    g.write_double_attribute(state_name::max_sigma1_pa, s.max_sigma1_pa);
    write_profile(g.create_group(state_name::profile_at_max_sigma1), s.profile_at_max_sigma1);
    g.write_double_attribute(state_name::max_window_sigma1_pa, s.max_window_sigma1_pa);
    g.write_double_attribute(state_name::below_since_strain, s.below_since_strain); // NaN: not below
    g.write_int_attribute(state_name::loading_begun, s.loading_begun ? 1 : 0);
    g.write_double_attribute(state_name::window_force_n, s.window_force_n);
    g.write_double_attribute(state_name::window_kinetic_energy_j, s.window_kinetic_energy_j);
    for (int k = 0; k < 3; ++k) g.write_double_attribute(state_name::pull_start_m[k], s.pull_start_m[k]);
    g.write_double_attribute(state_name::pull_force_sum_n, s.pull_force_sum_n);
    g.write_double_attribute(state_name::end_tension_sum_n, s.end_tension_sum_n);
    g.write_int_attribute(state_name::pull_steps_summed, static_cast<std::int64_t>(s.pull_steps_summed));
    g.write_double_attribute(state_name::wall_time_s, s.wall_time_s);
    g.write_int_attribute(state_name::live_springs_reported, s.live_springs_reported ? 1 : 0);
    io::Group result = g.create_group(state_name::result);
    write_free_standing_result(result, s.result);
}

eng::FreeStandingDriverState read_free_standing_driver_state(const io::Group& g)
{
    eng::FreeStandingDriverState s;
    s.steps = read_index(g, state_name::steps);
    const std::string phase = g.read_string_attribute(state_name::phase);
    bool known = false;
    for (auto p : {eng::FreeStandingPhase::removal, eng::FreeStandingPhase::settling, eng::FreeStandingPhase::dead_load,
             eng::FreeStandingPhase::loading, eng::FreeStandingPhase::pull_out})
        if (phase == eng::to_string(p)) {
            s.phase = p;
            known = true;
        }
    if (!known) throw std::runtime_error(g.path() + ": phase \"" + phase + "\" is not a phase of the free-standing test");
    s.phase_start_step = read_index(g, state_name::phase_start_step);
    if (s.phase_start_step > s.steps) throw std::runtime_error(g.path() + ": phase_start_step is past steps");
    s.reference_height_m = g.read_double_attribute(state_name::reference_height_m);
    s.reference_radius_m = g.read_double_attribute(state_name::reference_radius_m);
    s.last_sample_step = static_cast<std::uint64_t>(g.read_int_attribute(state_name::last_sample_step));
    s.next_snapshot = read_index(g, state_name::next_snapshot);
    s.max_sigma1_pa = g.read_double_attribute(state_name::max_sigma1_pa);
    s.profile_at_max_sigma1 = read_profile(g.open_group(state_name::profile_at_max_sigma1));
    s.max_window_sigma1_pa = g.read_double_attribute(state_name::max_window_sigma1_pa);
    s.below_since_strain = g.read_double_attribute(state_name::below_since_strain);
    s.loading_begun = g.read_int_attribute(state_name::loading_begun) != 0;
    s.window_force_n = g.read_double_attribute(state_name::window_force_n);
    s.window_kinetic_energy_j = g.read_double_attribute(state_name::window_kinetic_energy_j);
    for (int k = 0; k < 3; ++k) s.pull_start_m[k] = g.read_double_attribute(state_name::pull_start_m[k]);
    s.pull_force_sum_n = g.read_double_attribute(state_name::pull_force_sum_n);
    s.end_tension_sum_n = g.read_double_attribute(state_name::end_tension_sum_n);
    s.pull_steps_summed = read_index(g, state_name::pull_steps_summed);
    s.wall_time_s = g.read_double_attribute(state_name::wall_time_s);
    s.result = read_free_standing_result(g.open_group(state_name::result));
    s.live_springs_reported = read_live_springs_reported(g, s.result.warnings);
    return s;
}

void write_preparation_report(io::Group& g, const eng::PreparationReport& r)
{
    g.write_int_attribute(result_name(P::specimen, "grains"), static_cast<std::int64_t>(r.grains));
    g.write_int_attribute(result_name(P::specimen, "wire_nodes"), static_cast<std::int64_t>(r.wire_nodes));
    g.write_double_attribute(result_name(P::specimen, "wire_length_m"), r.wire_length_m);
    g.write_double_attribute(result_name(P::specimen, "nozzle_path_m"), r.nozzle_path_m);
    g.write_double_attribute(result_name(P::specimen, "pile_height_m"), r.pile_height_m);
    g.write_double_attribute(result_name(P::specimen, "sample_volume_m3"), r.sample_volume_m3);
    g.write_double_attribute(result_name(P::specimen, "grain_volume_fraction"), r.grain_volume_fraction);
    g.write_double_attribute(result_name(P::specimen, "wire_volume_fraction"), r.wire_volume_fraction);
    g.write_double_attribute(result_name(P::specimen, "core_grain_volume_fraction"), r.core_grain_volume_fraction);
    g.write_double_attribute(result_name(P::specimen, "core_wire_volume_fraction"), r.core_wire_volume_fraction);
    g.write_double_attribute(result_name(P::specimen, "simulated_time_s"), r.simulated_time_s);
    g.write_double_attribute(result_name(P::specimen, "wall_time_s"), r.wall_time_s);
    g.write_int_attribute(result_name(P::specimen, "steps"), static_cast<std::int64_t>(r.steps));
    g.write_double_attribute(result_name(P::specimen, "time_step_s"), r.time_step_s);
    g.write_int_attribute(result_name(P::specimen, "settled"), r.settled ? 1 : 0);
    g.write_int_attribute(result_name(P::specimen, "top_plate_wall"), static_cast<std::int64_t>(r.top_plate_wall));
    if (r.grain_sizes) {
        // The drawn grains against the requested curve (engine/specimen/grain_sizes.hpp).
        const eng::GrainSizeReport& z = *r.grain_sizes;
        io::Group s = g.create_group(result_name(P::specimen, "grain_sizes"));
        for (const auto& [n, f] : {std::pair{&requested_grain_sizes, &z.requested}, std::pair{&drawn_grain_sizes, &z.drawn}}) {
            s.write_double_attribute(n->d10_m, f->d10_m);
            s.write_double_attribute(n->d50_m, f->d50_m);
            s.write_double_attribute(n->d60_m, f->d60_m);
            s.write_double_attribute(n->uniformity_coefficient, f->uniformity_coefficient);
        }
        s.write_double_attribute(result_name(P::grain_sizes, "ks_distance"), z.ks_distance);
        s.write_double_attribute(result_name(P::grain_sizes, "ks_critical_1pct"), z.ks_critical_1pct);
        s.write_int_attribute(result_name(P::grain_sizes, "grains"), static_cast<std::int64_t>(z.grains));
    }
}

eng::PreparationReport read_preparation_report(const io::Group& g)
{
    eng::PreparationReport r;
    r.grains = read_index(g, result_name(P::specimen, "grains"));
    r.wire_nodes = read_index(g, result_name(P::specimen, "wire_nodes"));
    r.wire_length_m = g.read_double_attribute(result_name(P::specimen, "wire_length_m"));
    r.nozzle_path_m = g.read_double_attribute(result_name(P::specimen, "nozzle_path_m"));
    r.pile_height_m = g.read_double_attribute(result_name(P::specimen, "pile_height_m"));
    r.sample_volume_m3 = g.read_double_attribute(result_name(P::specimen, "sample_volume_m3"));
    r.grain_volume_fraction = g.read_double_attribute(result_name(P::specimen, "grain_volume_fraction"));
    r.wire_volume_fraction = g.read_double_attribute(result_name(P::specimen, "wire_volume_fraction"));
    r.core_grain_volume_fraction = g.read_double_attribute(result_name(P::specimen, "core_grain_volume_fraction"));
    r.core_wire_volume_fraction = g.read_double_attribute(result_name(P::specimen, "core_wire_volume_fraction"));
    r.simulated_time_s = g.read_double_attribute(result_name(P::specimen, "simulated_time_s"));
    r.wall_time_s = g.read_double_attribute(result_name(P::specimen, "wall_time_s"));
    r.steps = read_index(g, result_name(P::specimen, "steps"));
    r.time_step_s = g.read_double_attribute(result_name(P::specimen, "time_step_s"));
    r.settled = g.read_int_attribute(result_name(P::specimen, "settled")) != 0;
    r.top_plate_wall = read_index(g, result_name(P::specimen, "top_plate_wall"));
    if (g.exists(result_name(P::specimen, "grain_sizes"))) {
        const io::Group s = g.open_group(result_name(P::specimen, "grain_sizes"));
        eng::GrainSizeReport z;
        for (const auto& [n, f] : {std::pair{&requested_grain_sizes, &z.requested}, std::pair{&drawn_grain_sizes, &z.drawn}}) {
            f->d10_m = s.read_double_attribute(n->d10_m);
            f->d50_m = s.read_double_attribute(n->d50_m);
            f->d60_m = s.read_double_attribute(n->d60_m);
            f->uniformity_coefficient = s.read_double_attribute(n->uniformity_coefficient);
        }
        z.ks_distance = s.read_double_attribute(result_name(P::grain_sizes, "ks_distance"));
        z.ks_critical_1pct = s.read_double_attribute(result_name(P::grain_sizes, "ks_critical_1pct"));
        z.grains = read_index(s, result_name(P::grain_sizes, "grains"));
        r.grain_sizes = z;
    }
    return r;
}

namespace {

constexpr std::array preparation_phases{
    std::pair{eng::PreparationPhase::pouring, "pouring"},
    std::pair{eng::PreparationPhase::settling, "settling"},
    std::pair{eng::PreparationPhase::lowering_lid, "lowering_lid"},
    std::pair{eng::PreparationPhase::settling_under_lid, "settling_under_lid"},
    std::pair{eng::PreparationPhase::following_lid, "following_lid"},
};

} // namespace

void write_preparation_state(io::Group& g, const eng::PreparationDriverState& s)
{
    const auto phase = std::find_if(preparation_phases.begin(), preparation_phases.end(),
        [&](const auto& p) { return p.first == s.phase; });
    if (phase == preparation_phases.end()) throw std::runtime_error("unknown preparation phase");
    g.write_string_attribute(state_name::phase, phase->second);
    g.write_int_attribute(state_name::steps, static_cast<std::int64_t>(s.steps));
    g.write_int_attribute(state_name::rng_state, static_cast<std::int64_t>(s.rng_state)); // the same 64 bits
    g.write_double_attribute(state_name::owed_grains, s.owed_grains);
    g.write_double_attribute(state_name::next_batch_s, s.next_batch_s);
    g.write_double_attribute(state_name::poured_volume_m3, s.poured_volume_m3);
    g.write_double_attribute(state_name::pile_top_m, s.pile_top_m);
    g.write_double_attribute(state_name::nozzle_target_m, s.nozzle_target_m);
    g.write_int_attribute(state_name::laid_all, s.laid_all ? 1 : 0);
    g.write_double_attribute(state_name::nozzle_z_m, s.nozzle.z_m);
    g.write_double_attribute(state_name::nozzle_path_m, s.nozzle.path_m);
    g.write_double_attribute(state_name::nozzle_last_node_path_m, s.nozzle.last_node_path_m);
    g.write_double_attribute(state_name::nozzle_integration_s_m, s.nozzle.path_integration.s_m);
    g.write_double_attribute(state_name::nozzle_integration_theta_rad, s.nozzle.path_integration.theta_rad);
    g.write_int_attribute(state_name::settled_before_lid, s.settled_before_lid ? 1 : 0);
    g.write_int_attribute(state_name::settled_under_lid, s.settled_under_lid ? 1 : 0);
    g.write_int_attribute(state_name::top_plate_wall, static_cast<std::int64_t>(s.top_plate_wall));
    g.write_double_attribute(state_name::wall_time_s, s.wall_time_s);
}

eng::PreparationDriverState read_preparation_state(const io::Group& g)
{
    eng::PreparationDriverState s;
    const std::string phase = g.read_string_attribute(state_name::phase);
    const auto p = std::find_if(preparation_phases.begin(), preparation_phases.end(),
        [&](const auto& q) { return phase == q.second; });
    if (p == preparation_phases.end())
        throw std::runtime_error(g.path() + ": attribute phase is \"" + phase + "\", not a preparation phase");
    s.phase = p->first;
    s.steps = read_index(g, state_name::steps);
    s.rng_state = static_cast<std::uint64_t>(g.read_int_attribute(state_name::rng_state));
    s.owed_grains = g.read_double_attribute(state_name::owed_grains);
    s.next_batch_s = g.read_double_attribute(state_name::next_batch_s);
    s.poured_volume_m3 = g.read_double_attribute(state_name::poured_volume_m3);
    s.pile_top_m = g.read_double_attribute(state_name::pile_top_m);
    s.nozzle_target_m = g.read_double_attribute(state_name::nozzle_target_m);
    s.laid_all = g.read_int_attribute(state_name::laid_all) != 0;
    s.nozzle.z_m = g.read_double_attribute(state_name::nozzle_z_m);
    s.nozzle.path_m = g.read_double_attribute(state_name::nozzle_path_m);
    s.nozzle.last_node_path_m = g.read_double_attribute(state_name::nozzle_last_node_path_m);
    s.nozzle.path_integration.s_m = g.read_double_attribute(state_name::nozzle_integration_s_m);
    s.nozzle.path_integration.theta_rad = g.read_double_attribute(state_name::nozzle_integration_theta_rad);
    s.settled_before_lid = g.read_int_attribute(state_name::settled_before_lid) != 0;
    s.settled_under_lid = g.read_int_attribute(state_name::settled_under_lid) != 0;
    s.top_plate_wall = read_index(g, state_name::top_plate_wall);
    s.wall_time_s = g.read_double_attribute(state_name::wall_time_s);
    return s;
}

} // namespace wiredem::campaign
