// XDMF sidecar writer; see xdmf.hpp for the grids it describes. Every HDF5 reference
// is built from the dataset as found in the file (its shape and stored type), so the
// XML never names a dataset that does not exist or declares dimensions it does not
// have; arrays with an unexpected shape are left out rather than described wrongly.
#include "io/xdmf.hpp"

#include "core/format.hpp"
#include "io/atomic_file.hpp"

#include "io/hdf5.hpp"
#include "triaxial/result_names.hpp"

#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace wiredem::engine::io {

namespace {

// The names of result.h5 read here (triaxial/result_names.hpp). The
// specimen's bodies and a snapshot's are drawn by the same code: their
// datasets are spelled alike in both places.
using P = ResultPlace;
constexpr std::string_view grain_position_m = result_name(P::snapshot, "grain_position_m");
constexpr std::string_view grain_radius_m = result_name(P::snapshot, "grain_radius_m");
constexpr std::string_view grain_velocity_m_per_s = result_name(P::snapshot, "grain_velocity_m_per_s");
constexpr std::string_view grain_clump = result_name(P::specimen, "grain_clump");
constexpr std::string_view wire_node_position_m = result_name(P::snapshot, "wire_node_position_m");
constexpr std::string_view wire_segment_strain = result_name(P::snapshot, "wire_segment_strain");
constexpr std::string_view membrane_node_position_m = result_name(P::snapshot, "membrane_node_position_m");
constexpr std::string_view membrane_triangles = result_name(P::snapshot, "membrane_triangles");
constexpr std::string_view contact_bodies = result_name(P::snapshot, "contact_bodies");
constexpr std::string_view contact_force_n = result_name(P::snapshot, "contact_force_n");
constexpr std::string_view contact_normal_force_n = result_name(P::snapshot, "contact_normal_force_n");
static_assert(result_name(P::specimen, "grain_position_m") == grain_position_m
              && result_name(P::specimen, "grain_radius_m") == grain_radius_m
              && result_name(P::specimen, "wire_node_position_m") == wire_node_position_m
              && result_name(P::specimen, "membrane_node_position_m") == membrane_node_position_m);
constexpr std::string_view tests_group = result_name(P::root, "tests");
constexpr std::string_view specimen_group = result_name(P::root, "specimen");
constexpr std::string_view snapshots_group = result_name(P::record, "snapshots");

/// `parts` joined by '/': a path below a group.
std::string joined(std::initializer_list<std::string_view> parts)
{
    std::string out;
    for (std::string_view p : parts) {
        if (!out.empty()) out += '/';
        out += p;
    }
    return out;
}

/// One HDF5 dataset as XDMF sees it.
struct Array {
    std::string path;                ///< absolute HDF5 path
    std::vector<std::size_t> shape;  ///< stored extent
    std::string number_type;         ///< XDMF NumberType: Float, Int, UInt, Char, UChar
    std::size_t precision = 8;       ///< bytes per element

    [[nodiscard]] std::size_t rows() const { return shape.empty() ? 1 : shape.front(); }
    [[nodiscard]] std::size_t columns() const { return shape.size() == 2 ? shape[1] : 1; }
};

std::string escape(std::string_view s)
{
    std::string out;
    out.reserve(s.size());
    for (const char c : s) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&apos;"; break;
        default: out += c;
        }
    }
    return out;
}

/// 17 significant digits (%.17g): reads back as the same double.
std::string number_text(double x) { return format_number(x, 17); }

std::string dims_text(const std::vector<std::size_t>& shape)
{
    std::string s;
    for (const std::size_t d : shape) {
        if (!s.empty()) s += ' ';
        s += std::to_string(d);
    }
    return s.empty() ? "1" : s;
}

/// The dataset at `path` (relative to `g`) with its stored type, or nothing when it
/// is absent or not a plain integer/float array.
std::optional<Array> find_array(const Group& g, std::string_view path)
{
    if (!g.exists(path)) return std::nullopt;
    // A group of that name is not an array (H5Oopen + H5Iget_type: the same in
    // HDF5 1.10 and 1.12+, unlike H5Oget_info).
    const hid_t object = H5Oopen(g.id(), std::string(path).c_str(), H5P_DEFAULT);
    if (object < 0) {
        H5Eclear2(H5E_DEFAULT);
        return std::nullopt;
    }
    const bool is_dataset = H5Iget_type(object) == H5I_DATASET;
    H5Oclose(object);
    if (!is_dataset) return std::nullopt;
    const Dataset ds = g.open_dataset(path);
    Array a;
    a.path = ds.path();
    a.shape = ds.shape();
    const hid_t type = H5Dget_type(ds.id());
    if (type < 0) throw Hdf5Error("cannot get dataset type", ds.file_name(), ds.path(), "H5Dget_type failed");
    const H5T_class_t cls = H5Tget_class(type);
    a.precision = H5Tget_size(type);
    const H5T_sign_t sign = cls == H5T_INTEGER ? H5Tget_sign(type) : H5T_SGN_ERROR;
    H5Tclose(type);
    if (cls == H5T_FLOAT && (a.precision == 4 || a.precision == 8))
        a.number_type = "Float";
    else if (cls == H5T_INTEGER && a.precision == 1)
        a.number_type = sign == H5T_SGN_NONE ? "UChar" : "Char";
    else if (cls == H5T_INTEGER && (a.precision == 2 || a.precision == 4 || a.precision == 8))
        a.number_type = sign == H5T_SGN_NONE ? "UInt" : "Int";
    else
        return std::nullopt;
    return a;
}

/// An N×3 array (positions, velocities, forces), or nothing.
std::optional<Array> find_vectors(const Group& g, std::string_view path)
{
    auto a = find_array(g, path);
    if (!a || a->shape.size() != 2 || a->shape[1] != 3) return std::nullopt;
    return a;
}

/// A 1-D array of exactly `n` values (or an n×1 one), or nothing.
std::optional<Array> find_scalars(const Group& g, std::string_view path, std::size_t n)
{
    auto a = find_array(g, path);
    if (!a || a->shape.empty() || a->shape.size() > 2 || a->rows() != n || a->columns() != 1) return std::nullopt;
    return a;
}

/// The wire segments removed in `g`'s wire_breaks (a test's or the
/// specimen's) at test time `up_to_s` or before, appended to `out`.
void append_removed_segments(const Group& g, double up_to_s, std::vector<std::int64_t>& out)
{
    const std::string segment_path = joined({result_name(P::record, "wire_breaks"), result_name(P::wire_breaks, "segment")});
    const std::string time_path = joined({result_name(P::record, "wire_breaks"), result_name(P::wire_breaks, "time_s")});
    if (!g.exists(segment_path) || !g.exists(time_path)) return;
    const std::vector<std::int64_t> segment = g.open_dataset(segment_path).read_int64s();
    const std::vector<double> time = g.open_dataset(time_path).read_doubles();
    for (std::size_t i = 0; i < segment.size() && i < time.size(); ++i)
        if (time[i] <= up_to_s) out.push_back(segment[i]);
}

/// Sorted and without repeats, for binary_search.
std::vector<std::int64_t> sorted_set(std::vector<std::int64_t> v)
{
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    return v;
}

/// Indented XML text, one element per line.
class Xml {
public:
    void line(const std::string& text) { out_ << std::string(2 * depth_, ' ') << text << '\n'; }
    void open(const std::string& tag_and_attributes)
    {
        line("<" + tag_and_attributes + ">");
        ++depth_;
    }
    void close(const std::string& tag)
    {
        --depth_;
        line("</" + tag + ">");
    }
    [[nodiscard]] std::string str() const { return out_.str(); }

private:
    std::ostringstream out_;
    int depth_ = 0;
};

/// Writes the XDMF elements of one result file.
class Writer {
public:
    Writer(std::string h5_reference, XdmfSummary& summary) : ref_(escape(h5_reference)), summary_(summary) {}

    Xml xml;

    /// <DataItem> naming an HDF5 dataset, with its stored dimensions and type.
    void data_item(const Array& a)
    {
        xml.line("<DataItem Dimensions=\"" + dims_text(a.shape) + "\" NumberType=\"" + a.number_type
                 + "\" Precision=\"" + std::to_string(a.precision) + "\" Format=\"HDF\">" + ref_ + ":"
                 + escape(a.path) + "</DataItem>");
    }

    /// <DataItem> holding integers inline, `columns` per row.
    void inline_item(const std::vector<std::int64_t>& values, std::size_t columns)
    {
        const std::size_t rows = values.size() / columns;
        xml.open("DataItem Dimensions=\"" + std::to_string(rows) + " " + std::to_string(columns)
                 + "\" NumberType=\"Int\" Precision=\"" + (fits_int32(values) ? "4" : "8") + "\" Format=\"XML\"");
        std::string row;
        for (std::size_t r = 0; r < rows; ++r) {
            row.clear();
            for (std::size_t c = 0; c < columns; ++c) {
                if (c) row += ' ';
                row += std::to_string(values[r * columns + c]);
            }
            xml.line(row);
        }
        xml.close("DataItem");
    }

    /// <DataItem> holding N doubles inline (the strain of a cut wire's segments).
    void inline_scalars(const std::vector<double>& values)
    {
        xml.open("DataItem Dimensions=\"" + std::to_string(values.size()) + "\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\"");
        for (const double v : values) xml.line(number_text(v));
        xml.close("DataItem");
    }

    /// <DataItem> holding N×3 doubles inline (contact end points).
    void inline_item(const std::vector<double>& xyz)
    {
        xml.open("DataItem Dimensions=\"" + std::to_string(xyz.size() / 3)
                 + " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\"");
        for (std::size_t r = 0; 3 * r < xyz.size(); ++r) {
            // 9 significant digits: far below a grain radius, a third of the text of %.17g
            xml.line(format_number(xyz[3 * r], 9) + ' ' + format_number(xyz[3 * r + 1], 9) + ' '
                     + format_number(xyz[3 * r + 2], 9));
        }
        xml.close("DataItem");
    }

    /// A Polyvertex topology of n one-node cells. ParaView's XDMF 3 reader makes no
    /// cells without a connectivity array, hence the explicit 0 … n−1.
    void vertices(std::size_t n)
    {
        xml.open("Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" + std::to_string(n)
                 + "\" NodesPerElement=\"1\"");
        std::vector<std::int64_t> ids(n);
        for (std::size_t i = 0; i < n; ++i) ids[i] = static_cast<std::int64_t>(i);
        inline_item(ids, 1);
        xml.close("Topology");
    }

    void attribute(const std::string& name, const char* type, const char* center, const Array& a)
    {
        xml.open("Attribute Name=\"" + escape(name) + "\" AttributeType=\"" + type + "\" Center=\"" + center + "\"");
        data_item(a);
        xml.close("Attribute");
    }

    void geometry(const Array& positions)
    {
        xml.open("Geometry GeometryType=\"XYZ\"");
        data_item(positions);
        xml.close("Geometry");
    }

    /// Grains as vertices with radius and (optionally) velocity.
    void grains(const Group& g, bool with_velocity)
    {
        const auto pos = find_vectors(g, grain_position_m);
        if (!pos || pos->rows() == 0) return;
        const std::size_t n = pos->rows();
        xml.open("Grid Name=\"grains\" GridType=\"Uniform\"");
        vertices(n);
        geometry(*pos);
        if (const auto r = find_scalars(g, grain_radius_m, n)) attribute("radius_m", "Scalar", "Node", *r);
        // Clumps: each sphere is a vertex; its clump's index (−1: a free grain).
        if (const auto c = find_scalars(g, grain_clump, n)) attribute("clump", "Scalar", "Node", *c);
        if (with_velocity)
            if (const auto v = find_vectors(g, grain_velocity_m_per_s); v && v->rows() == n)
                attribute("velocity_m_per_s", "Vector", "Node", *v);
        xml.close("Grid");
        ++summary_.grids;
    }

    /// The wire as its W − 1 two-node segments but those `removed` (sorted:
    /// broken or cut by then), with the segment strain. A whole wire's strain
    /// is a reference to the file; with segments removed, the others' are
    /// written inline.
    void wire(const Group& g, bool with_strain, const std::vector<std::int64_t>& removed)
    {
        const auto pos = find_vectors(g, wire_node_position_m);
        if (!pos || pos->rows() < 2) return;
        const std::size_t segments = pos->rows() - 1;
        std::vector<std::int64_t> pairs, kept;
        pairs.reserve(2 * segments);
        for (std::size_t s = 0; s < segments; ++s) {
            if (std::binary_search(removed.begin(), removed.end(), static_cast<std::int64_t>(s))) continue;
            kept.push_back(static_cast<std::int64_t>(s));
            pairs.push_back(static_cast<std::int64_t>(s));
            pairs.push_back(static_cast<std::int64_t>(s + 1));
        }
        if (kept.empty()) return;
        xml.open("Grid Name=\"wire\" GridType=\"Uniform\"");
        xml.open("Topology TopologyType=\"Polyline\" NumberOfElements=\"" + std::to_string(kept.size())
                 + "\" NodesPerElement=\"2\"");
        inline_item(pairs, 2);
        xml.close("Topology");
        geometry(*pos);
        if (with_strain)
            if (const auto e = find_scalars(g, wire_segment_strain, segments)) {
                if (kept.size() == segments) {
                    attribute("segment_strain", "Scalar", "Cell", *e);
                } else {
                    const std::vector<double> all = g.open_dataset(wire_segment_strain).read_doubles();
                    std::vector<double> values;
                    values.reserve(kept.size());
                    for (const std::int64_t s : kept) values.push_back(all[static_cast<std::size_t>(s)]);
                    xml.open("Attribute Name=\"segment_strain\" AttributeType=\"Scalar\" Center=\"Cell\"");
                    inline_scalars(values);
                    xml.close("Attribute");
                }
            }
        xml.close("Grid");
        ++summary_.grids;
    }

    /// The membrane as a triangle surface (`triangles` from `tri_group` when given).
    void membrane(const Group& g, const std::optional<Array>& triangles)
    {
        const auto pos = find_vectors(g, membrane_node_position_m);
        if (!pos || pos->rows() == 0) return;
        xml.open("Grid Name=\"membrane\" GridType=\"Uniform\"");
        if (triangles) {
            xml.open("Topology TopologyType=\"Triangle\" NumberOfElements=\"" + std::to_string(triangles->rows())
                     + "\" NodesPerElement=\"3\"");
            data_item(*triangles);
            xml.close("Topology");
        } else {
            vertices(pos->rows());
        }
        geometry(*pos);
        xml.close("Grid");
        ++summary_.grids;
    }

    /// The force network: one segment per contact pair, between the bodies' centres.
    /// The end points are written inline: the pair's bodies live in up to two of the
    /// three position datasets, and ParaView's XDMF 3 reader does not evaluate
    /// Function (JOIN) or HyperSlab items that could combine them.
    void contacts(const Group& g)
    {
        const auto bodies = find_array(g, contact_bodies);
        if (!bodies || bodies->shape.size() != 2 || bodies->shape[1] != 4 || bodies->rows() == 0) return;
        const std::size_t p = bodies->rows();
        const std::array<std::string_view, 3> names = {
            grain_position_m, wire_node_position_m, membrane_node_position_m};
        std::array<std::vector<double>, 3> pos; // by kind: 0 grain, 1 wire, 2 membrane
        for (std::size_t k = 0; k < 3; ++k)
            if (find_vectors(g, names[k])) pos[k] = g.open_dataset(names[k]).read_doubles();
        const std::vector<std::int64_t> raw = g.open_dataset(contact_bodies).read_int64s();
        std::vector<double> xyz;
        xyz.reserve(6 * p);
        for (std::size_t c = 0; c < p; ++c) {
            for (std::size_t end = 0; end < 2; ++end) {
                const std::int64_t kind = raw[4 * c + 2 * end], index = raw[4 * c + 2 * end + 1];
                // A reference outside the stored bodies: the file is inconsistent;
                // describe no force network rather than a wrong one.
                if (kind < 0 || kind > 2 || index < 0
                    || 3 * static_cast<std::size_t>(index) + 3 > pos[static_cast<std::size_t>(kind)].size())
                    return;
                const double* x = &pos[static_cast<std::size_t>(kind)][3 * static_cast<std::size_t>(index)];
                xyz.insert(xyz.end(), x, x + 3);
            }
        }
        std::vector<std::int64_t> ends(2 * p);
        for (std::size_t i = 0; i < 2 * p; ++i) ends[i] = static_cast<std::int64_t>(i);
        xml.open("Grid Name=\"contacts\" GridType=\"Uniform\"");
        xml.open("Topology TopologyType=\"Polyline\" NumberOfElements=\"" + std::to_string(p)
                 + "\" NodesPerElement=\"2\"");
        inline_item(ends, 2);
        xml.close("Topology");
        xml.open("Geometry GeometryType=\"XYZ\"");
        inline_item(xyz);
        xml.close("Geometry");
        if (const auto f = find_scalars(g, contact_normal_force_n, p)) attribute("normal_force_n", "Scalar", "Cell", *f);
        if (const auto f = find_vectors(g, contact_force_n); f && f->rows() == p)
            attribute("force_n", "Vector", "Cell", *f);
        xml.close("Grid");
        ++summary_.grids;
    }

private:
    static bool fits_int32(const std::vector<std::int64_t>& v)
    {
        return std::all_of(v.begin(), v.end(), [](std::int64_t x) { return x >= INT32_MIN && x <= INT32_MAX; });
    }

    std::string ref_;
    XdmfSummary& summary_;
};

/// Names of the children of `g` that start with `prefix` and end in a number,
/// in ascending numeric order.
std::vector<std::string> numbered_children(const Group& g, std::string_view prefix)
{
    std::vector<std::pair<long long, std::string>> found;
    for (const std::string& name : g.child_names()) {
        if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
        const std::string digits = name.substr(prefix.size());
        if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
        found.emplace_back(std::stoll(digits), name);
    }
    std::sort(found.begin(), found.end());
    std::vector<std::string> names;
    for (auto& f : found) names.push_back(std::move(f.second));
    return names;
}

double attribute_or(const Object& o, std::string_view name, double fallback)
{
    return o.has_attribute(name) ? o.read_double_attribute(name) : fallback;
}

bool strictly_increasing(const std::vector<double>& v)
{
    for (std::size_t i = 1; i < v.size(); ++i)
        if (!(v[i] > v[i - 1])) return false;
    return true;
}

} // namespace

std::string xdmf_text(const std::filesystem::path& h5_path, const std::string& h5_reference, XdmfSummary* summary)
{
    XdmfSummary local;
    XdmfSummary& sum = summary ? *summary : local;
    sum = {};
    const File file = File::open_read_only(h5_path);
    const Group root = file.root();
    Writer w(h5_reference, sum);
    Xml& xml = w.xml;
    xml.line("<?xml version=\"1.0\" encoding=\"utf-8\"?>");
    xml.line("<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>");
    xml.open("Xdmf Version=\"3.0\"");
    xml.open("Domain");
    constexpr std::string_view format_name = result_name(P::root, "format");
    const std::string format = root.has_attribute(format_name) ? root.read_string_attribute(format_name) : "unknown";
    xml.line("<Information Name=\"source\" Value=\"" + escape(h5_reference) + " (" + escape(format)
             + "), written by wiredem\"/>");

    // Tests (and their snapshot groups), by ascending confining pressure.
    struct TestGroup {
        double pressure_pa;
        std::string name;
        std::vector<std::string> snapshots;
    };
    std::vector<TestGroup> tests;
    if (root.exists(tests_group)) {
        const Group all = root.open_group(tests_group);
        for (const std::string& name : all.child_names()) {
            if (!all.exists(joined({name, snapshots_group}))) continue;
            const Group t = all.open_group(name);
            tests.push_back({attribute_or(t, result_name(P::test, "confining_pressure_pa"), 0.0), name,
                numbered_children(t.open_group(snapshots_group), result_name(P::snapshots, "snapshot_"))});
        }
        std::stable_sort(tests.begin(), tests.end(),
            [](const TestGroup& a, const TestGroup& b) { return a.pressure_pa < b.pressure_pa; });
    }

    // The specimen. Its membrane triangles: those of the first snapshot whose
    // membrane has as many nodes (the mesh does not change during a test).
    if (root.exists(specimen_group)) {
        const Group sp = root.open_group(specimen_group);
        std::optional<Array> triangles;
        const auto sp_nodes = find_vectors(sp, membrane_node_position_m);
        for (const TestGroup& t : tests) {
            if (triangles || !sp_nodes || t.snapshots.empty()) break;
            const Group s = root.open_group(joined({tests_group, t.name, snapshots_group, t.snapshots.front()}));
            const auto nodes = find_vectors(s, membrane_node_position_m);
            const auto tri = find_array(s, membrane_triangles);
            if (nodes && nodes->rows() == sp_nodes->rows() && tri && tri->shape.size() == 2 && tri->shape[1] == 3
                && tri->rows() > 0 && tri->number_type != "Float")
                triangles = tri;
        }
        xml.open("Grid Name=\"specimen\" GridType=\"Collection\" CollectionType=\"Spatial\"");
        sum.specimen = true;
        w.grains(sp, false);
        std::vector<std::int64_t> prepared_removed;
        append_removed_segments(sp, std::numeric_limits<double>::infinity(), prepared_removed);
        w.wire(sp, false, sorted_set(prepared_removed));
        w.membrane(sp, triangles);
        xml.close("Grid");
    }

    for (const TestGroup& t : tests) {
        if (t.snapshots.empty()) continue;
        const std::string base = joined({tests_group, t.name, snapshots_group}) + '/';
        std::vector<double> strain, requested, time_s;
        for (const std::string& s : t.snapshots) {
            const Group g = root.open_group(base + s);
            strain.push_back(attribute_or(g, result_name(P::snapshot, "axial_strain"), -1.0));
            requested.push_back(attribute_or(g, result_name(P::snapshot, "requested_axial_strain"), -1.0));
            time_s.push_back(attribute_or(g, result_name(P::snapshot, "time_s"), 0.0));
        }
        // Time = the requested strain: the same in every test of a campaign, so that
        // ParaView shows all tests at each step (its XDMF 3 readers match times
        // exactly). ParaView needs strictly increasing times within a collection.
        const char* time_is = "requested_axial_strain";
        std::vector<double> times = requested;
        if (!strictly_increasing(times)) {
            times = strain;
            time_is = "axial_strain";
        }
        if (!strictly_increasing(times)) {
            for (std::size_t k = 0; k < times.size(); ++k) times[k] = static_cast<double>(k);
            time_is = "snapshot index";
        }
        xml.open("Grid Name=\"" + escape(t.name) + "\" GridType=\"Collection\" CollectionType=\"Temporal\"");
        xml.line("<Information Name=\"time\" Value=\"" + std::string(time_is) + "\"/>");
        for (std::size_t k = 0; k < t.snapshots.size(); ++k) {
            const Group g = root.open_group(base + t.snapshots[k]);
            xml.open("Grid Name=\"" + escape(t.snapshots[k]) + "\" GridType=\"Collection\" CollectionType=\"Spatial\"");
            xml.line("<Time Value=\"" + number_text(times[k]) + "\"/>");
            xml.line("<Information Name=\"time_s\" Value=\"" + number_text(time_s[k]) + "\"/>");
            xml.line("<Information Name=\"axial_strain\" Value=\"" + number_text(strain[k]) + "\"/>");
            std::optional<Array> tri = find_array(g, membrane_triangles);
            if (tri && (tri->shape.size() != 2 || tri->shape[1] != 3 || tri->rows() == 0 || tri->number_type == "Float"))
                tri.reset();
            w.grains(g, true);
            // The wire as it was at the snapshot: without the segments cut or
            // broken in the preparation, and in this test up to then.
            std::vector<std::int64_t> removed;
            if (root.exists(specimen_group))
                append_removed_segments(root.open_group(specimen_group), std::numeric_limits<double>::infinity(), removed);
            append_removed_segments(root.open_group(joined({tests_group, t.name})), time_s[k], removed);
            w.wire(g, true, sorted_set(std::move(removed)));
            w.membrane(g, tri);
            w.contacts(g);
            xml.close("Grid");
            ++sum.snapshots;
        }
        xml.close("Grid");
        ++sum.tests;
    }
    xml.close("Domain");
    xml.close("Xdmf");
    return xml.str();
}

XdmfSummary write_xdmf(const std::filesystem::path& h5_path, std::filesystem::path xdmf_path)
{
    if (xdmf_path.empty()) xdmf_path = std::filesystem::path(h5_path).replace_extension(".xdmf");
    // The reference is relative to the XDMF file's directory, so the pair can move.
    std::error_code ec;
    const std::filesystem::path dir = std::filesystem::absolute(xdmf_path, ec).parent_path();
    std::filesystem::path ref = ec ? h5_path : std::filesystem::relative(std::filesystem::absolute(h5_path), dir, ec);
    if (ec || ref.empty()) ref = std::filesystem::absolute(h5_path);

    XdmfSummary summary;
    const std::string text = xdmf_text(h5_path, ref.generic_string(), &summary);
    write_text_file_atomically(xdmf_path, text);
    return summary;
}

} // namespace wiredem::engine::io
