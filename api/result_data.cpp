// Result data as JSON (api/result_data.hpp).
#include "api/result_data.hpp"
#include "api/json_text.hpp"

#include "analysis/autocorrelation.hpp"
#include "triaxial/result_names.hpp"
#include "triaxial/series_columns.hpp"

#include <boost/json.hpp>
#include <hdf5.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string_view>

namespace wiredem::api {
namespace json = boost::json;
namespace io = engine::io;
using P = engine::ResultPlace;

namespace {

bool is_numeric_dataset(const io::Dataset& d, H5T_class_t* cls_out = nullptr)
{
    const hid_t type = H5Dget_type(static_cast<hid_t>(d.id()));
    const H5T_class_t cls = H5Tget_class(type);
    H5Tclose(type);
    if (cls_out) *cls_out = cls;
    return cls == H5T_INTEGER || cls == H5T_FLOAT;
}

json::value units_of(const io::Dataset& d)
{
    constexpr std::string_view units = engine::result_name(P::dataset, "units");
    return d.has_attribute(units) ? json::value(d.read_string_attribute(units)) : json::value(nullptr);
}

} // namespace

json::object attributes_of(const io::Object& o)
{
    json::object out;
    const hid_t id = static_cast<hid_t>(o.id());
    H5O_info_t info{};
    if (H5Oget_info2(id, &info, H5O_INFO_NUM_ATTRS) < 0) return out;
    for (hsize_t i = 0; i < info.num_attrs; ++i) {
        const ssize_t len = H5Aget_name_by_idx(id, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
        if (len <= 0) continue;
        std::string name(static_cast<std::size_t>(len), '\0');
        H5Aget_name_by_idx(id, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size() + 1, H5P_DEFAULT);
        const hid_t attr = H5Aopen(id, name.c_str(), H5P_DEFAULT);
        if (attr < 0) continue;
        const hid_t type = H5Aget_type(attr);
        const H5T_class_t cls = H5Tget_class(type);
        H5Tclose(type);
        H5Aclose(attr);
        if (cls == H5T_STRING) out[name] = o.read_string_attribute(name);
        else if (cls == H5T_INTEGER) out[name] = o.read_int_attribute(name);
        else if (cls == H5T_FLOAT) out[name] = finite_or_null(o.read_double_attribute(name));
    }
    return out;
}

std::string snapshot_path(std::size_t k)
{
    // Appended rather than chained: GCC 12 at -O3 sees a false
    // -Warray-bounds in "…" + std::string(…) + std::to_string(…).
    std::string path(engine::result_name(P::record, "snapshots"));
    path += '/';
    path += snapshot_prefix;
    path += std::to_string(k);
    return path;
}

std::string test_path(const std::string& name)
{
    std::string path(tests_group);
    path += '/';
    path += name;
    return path;
}

std::vector<std::string> test_names(const io::Group& root)
{
    std::vector<std::pair<double, std::string>> found;
    if (!root.exists(tests_group)) return {};
    const io::Group all = root.open_group(tests_group);
    for (const std::string& name : all.child_names()) {
        const io::Group t = all.open_group(name);
        constexpr std::string_view pressure = engine::result_name(P::test, "confining_pressure_pa");
        found.emplace_back(t.has_attribute(pressure) ? t.read_double_attribute(pressure) : 0.0, name);
    }
    std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::string> names;
    for (auto& f : found) names.push_back(std::move(f.second));
    return names;
}

std::vector<std::size_t> snapshot_indices(const io::Group& test)
{
    std::vector<std::size_t> out;
    constexpr std::string_view snapshots = engine::result_name(P::record, "snapshots");
    if (!test.exists(snapshots)) return out;
    for (const std::string& name : test.open_group(snapshots).child_names()) {
        if (name.size() <= snapshot_prefix.size() || name.compare(0, snapshot_prefix.size(), snapshot_prefix) != 0) continue;
        std::size_t k = 0;
        const char* first = name.data() + snapshot_prefix.size();
        const char* last = name.data() + name.size();
        auto [p, ec] = std::from_chars(first, last, k);
        if (ec == std::errc() && p == last) out.push_back(k);
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<std::string> series_columns(const io::Group& test)
{
    std::vector<std::string> out;
    for (const std::string& name : test.child_names()) {
        H5O_info_t info{};
        if (H5Oget_info_by_name2(static_cast<hid_t>(test.id()), name.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0
            || info.type != H5O_TYPE_DATASET)
            continue;
        const io::Dataset d = test.open_dataset(name);
        if (d.shape().size() == 1 && is_numeric_dataset(d)) out.push_back(name);
    }
    return out;
}

json::array arrays_of(const io::Group& g, const std::string& url_base)
{
    json::array out;
    for (const std::string& name : g.child_names()) {
        H5O_info_t info{};
        if (H5Oget_info_by_name2(static_cast<hid_t>(g.id()), name.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0
            || info.type != H5O_TYPE_DATASET)
            continue;
        const io::Dataset d = g.open_dataset(name);
        H5T_class_t cls{};
        if (!is_numeric_dataset(d, &cls)) continue;
        json::array shape;
        for (std::size_t n : d.shape()) shape.push_back(n);
        json::object a{{"name", name}, {"shape", std::move(shape)}, {"dtype", cls == H5T_INTEGER ? "int32" : "float32"},
            {"units", units_of(d)},
            {"url", url_base + "/" + name}};
        out.push_back(std::move(a));
    }
    return out;
}

std::vector<std::size_t> decimated_rows(std::size_t rows, std::size_t max_points)
{
    std::vector<std::size_t> keep;
    if (rows <= max_points) {
        keep.resize(rows);
        for (std::size_t i = 0; i < rows; ++i) keep[i] = i;
        return keep;
    }
    keep.resize(max_points);
    // Row k·(rows−1)/(max_points−1), rounded to nearest, in integers: exact at both ends.
    const std::size_t span = rows - 1, steps = max_points - 1;
    for (std::size_t k = 0; k < max_points; ++k) keep[k] = (k * span + steps / 2) / steps;
    return keep;
}

json::object tests_json(const io::Group& root, const std::string& url_base)
{
    json::array tests;
    for (const std::string& name : test_names(root)) {
        const io::Group t = root.open_group(test_path(name));
        json::array columns;
        std::size_t rows = 0;
        for (const std::string& c : series_columns(t)) {
            const io::Dataset d = t.open_dataset(c);
            rows = std::max(rows, d.shape()[0]);
            columns.push_back(json::object{{"name", c}, {"units", units_of(d)}});
        }
        json::array snaps;
        for (std::size_t k : snapshot_indices(t)) {
            const io::Group s = t.open_group(snapshot_path(k));
            json::object o = attributes_of(s);
            o["index"] = k;
            o["url"] = url_base + "/tests/" + name + "/snapshots/" + std::to_string(k);
            snaps.push_back(std::move(o));
        }
        tests.push_back(json::object{{"name", name}, {"rows", rows}, {"attributes", attributes_of(t)},
            {"columns", std::move(columns)}, {"snapshots", std::move(snaps)},
            {"series_url", url_base + "/tests/" + name + "/series"}});
    }
    return json::object{{"tests", std::move(tests)}};
}

std::vector<std::string> free_standing_series_columns(const io::Group& g)
{
    std::vector<std::string> out = series_columns(g);
    // The series' rows: time_s's (every row has a time).
    const std::string time(engine::series_column("time_s").name);
    const std::size_t rows = g.exists(time) ? g.open_dataset(time).shape()[0] : 0;
    std::erase_if(out, [&](const std::string& c) {
        return std::find(free_standing_wire_arrays.begin(), free_standing_wire_arrays.end(), c) != free_standing_wire_arrays.end()
            || g.open_dataset(c).shape()[0] != rows;  // volumetric_strain: not derived for this test
    });
    return out;
}

json::object free_standing_json(const io::Group& g, const std::string& url_base, double l_w)
{
    const std::string base = url_base + "/" + std::string(free_standing_group);
    json::array columns;
    std::size_t rows = 0;
    for (const std::string& c : free_standing_series_columns(g)) {
        const io::Dataset d = g.open_dataset(c);
        rows = std::max(rows, d.shape()[0]);
        columns.push_back(json::object{{"name", c}, {"units", units_of(d)}});
    }
    const auto numbers = [](const std::vector<double>& v) {
        json::array a;
        a.reserve(v.size());
        for (double x : v) a.push_back(finite_or_null(x));
        return a;
    };
    json::object profiles;
    for (std::string_view name : free_standing_profiles) {
        const std::string n(name);
        if (!g.exists(n)) {
            profiles[n] = nullptr;
            continue;
        }
        const io::Group p = g.open_group(n);
        json::array grains;
        constexpr std::string_view height = engine::result_name(P::profile, "height_m"),
                                   radius = engine::result_name(P::profile, "radius_m"),
                                   grains_in_slice = engine::result_name(P::profile, "grains");
        for (std::int64_t k : p.open_dataset(grains_in_slice).read_int64s()) grains.push_back(k);
        profiles[n] = json::object{{height, numbers(p.open_dataset(height).read_doubles())},
            {radius, numbers(p.open_dataset(radius).read_doubles())}, {grains_in_slice, std::move(grains)}};
    }
    json::value wire = nullptr;
    const std::string strain_name(free_standing_wire_arrays[0]), tension_name(free_standing_wire_arrays[1]);
    if (g.exists(strain_name) && g.exists(tension_name)) {
        const std::vector<double> strain = g.open_dataset(strain_name).read_doubles();
        json::array distance;
        for (std::size_t k = 0; k < strain.size(); ++k) distance.push_back((static_cast<double>(k) + 0.5) * l_w);
        wire = json::object{{"segment_length_m", l_w}, {"distance_m", std::move(distance)}, {"strain", numbers(strain)},
            {"tension_n", numbers(g.open_dataset(tension_name).read_doubles())}};
    }
    json::array snaps;
    for (std::size_t k : snapshot_indices(g)) {
        json::object o = attributes_of(g.open_group(snapshot_path(k)));
        o["index"] = k;
        o["url"] = base + "/snapshots/" + std::to_string(k);
        snaps.push_back(std::move(o));
    }
    json::value peak = nullptr;
    if (g.exists(std::string(free_standing_peak_snapshot))) {
        json::object o = attributes_of(g.open_group(std::string(free_standing_peak_snapshot)));
        o["url"] = base + "/" + std::string(free_standing_peak_snapshot);
        peak = std::move(o);
    }
    json::value pull_out = nullptr; // the pull-out's rows, by column, with their units
    if (g.exists(std::string(pull_out_group))) {
        const io::Group p = g.open_group(std::string(pull_out_group));
        json::object o;
        for (std::string_view c : {engine::result_name(P::pull_out, "time_s"), engine::result_name(P::pull_out, "pulled_length_m"),
                 engine::result_name(P::pull_out, "pull_force_n"), engine::result_name(P::pull_out, "end_tension_n"),
                 engine::result_name(P::pull_out, "wire_in_column_m"), engine::result_name(P::pull_out, "grains_in_column")})
            if (p.exists(c)) {
                const io::Dataset d = p.open_dataset(c);
                o[c] = json::object{{"units", units_of(d)}, {"values", numbers(d.read_doubles())}};
            }
        pull_out = std::move(o);
    }
    return json::object{{"name", std::string(free_standing_group)}, {"rows", rows}, {"attributes", attributes_of(g)},
        {"columns", std::move(columns)}, {"profiles", std::move(profiles)}, {"wire_at_peak", std::move(wire)},
        {"pull_out", std::move(pull_out)},
        {"snapshots", std::move(snaps)}, {"peak_snapshot", std::move(peak)}, {"series_url", base + "/series"}};
}

json::object series_json(const io::Group& t, const std::string& name, const std::vector<std::string>& columns,
    std::size_t max_points)
{
    std::vector<SeriesColumn> read;
    for (const auto& c : columns.empty() ? series_columns(t) : columns) {
        const io::Dataset d = t.open_dataset(c);
        std::optional<std::string> units;
        if (d.has_attribute("units")) units = d.read_string_attribute("units");
        read.push_back({c, std::move(units), d.read_doubles()});
    }
    return series_json(name, read, max_points);
}

json::object series_json(const std::string& name, const std::vector<SeriesColumn>& columns, std::size_t max_points)
{
    std::size_t rows = 0;
    for (const auto& c : columns) rows = std::max(rows, c.values.size());
    for (const auto& c : columns)
        if (c.values.size() != rows)
            throw std::runtime_error("test " + name + ": column " + c.name + " has " + std::to_string(c.values.size())
                                     + " rows, others " + std::to_string(rows));
    const std::vector<std::size_t> keep = decimated_rows(rows, max_points);
    json::object cols, units;
    for (const auto& c : columns) {
        json::array a;
        a.reserve(keep.size());
        for (std::size_t r : keep) a.push_back(finite_or_null(c.values[r]));
        cols[c.name] = std::move(a);
        units[c.name] = c.units ? json::value(*c.units) : json::value(nullptr);
    }
    json::array row_index;
    for (std::size_t r : keep) row_index.push_back(r);
    return json::object{{"test", name}, {"rows", rows}, {"returned_rows", keep.size()}, {"row_index", std::move(row_index)},
        {"units", std::move(units)}, {"columns", std::move(cols)}};
}

json::object wire_autocorrelation_json(std::span<const double> strain, double l_w)
{
    json::object body{{"segment_length_m", l_w}, {"segments", strain.size()}};
    const auto ac = engine::analysis::autocorrelation(strain, l_w);
    if (!ac.ok()) {
        body["error"] = ac.error();
        body["lag_m"] = json::array();
        body["coefficients"] = json::array();
        body["first_maximum_lag_m"] = nullptr;
        body["prominent_maximum_lag_m"] = nullptr;
        return body;
    }
    json::array lag, r;
    for (std::size_t k = 0; k < ac.value().coefficients.size(); ++k) {
        lag.push_back(static_cast<double>(k) * l_w);
        r.push_back(finite_or_null(ac.value().coefficients[k]));
    }
    body["error"] = nullptr;
    body["lag_m"] = std::move(lag);
    body["coefficients"] = std::move(r);
    body["mean"] = finite_or_null(ac.value().mean);
    body["variance"] = finite_or_null(ac.value().variance);
    const auto number_or_null = [](std::optional<double> x) { return x ? finite_or_null(*x) : json::value(nullptr); };
    body["first_maximum_lag_m"] = number_or_null(ac.value().first_maximum_lag_m);
    body["prominent_maximum_lag_m"] = number_or_null(ac.value().prominent_maximum_lag_m);
    return body;
}

} // namespace wiredem::api
