// XDMF sidecar (engine/io/xdmf): a small result file in the layout of docs/results.md,
// written through the HDF5 layer the way `wiredem run` writes it, gets a sidecar that
// is parsed back as XML and checked against the HDF5 file: every HDF DataItem names an
// existing dataset with its dimensions and number type, topologies agree with their
// geometry and attributes, the wire has nodes − 1 segments, the force network joins
// the right bodies, tests become temporal collections. When ParaView's pvpython is
// installed, ParaView itself reads the file back.
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"
#include "temp_dir.hpp"
#ifdef WIREDEM_BIN
#include "api/job_spec.hpp"
#include "api/result_data.hpp"

#include <boost/json/serialize.hpp>
#endif

#include <hdf5.h>

#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

using namespace wiredem::engine;
using namespace wiredem::engine::io;
namespace fs = std::filesystem;
using boost::property_tree::ptree;
using wiredem::engine::io::test::TempDir;

namespace {


/// Sizes of the synthetic result file.
struct Sizes {
    std::size_t grains = 5;
    std::size_t wire_nodes = 4;
    std::size_t membrane_nodes = 6;
};

void units(Dataset d, const char* u) { d.write_string_attribute("units", u); }

std::vector<Vec3> points(std::size_t n, double z0)
{
    std::vector<Vec3> p;
    for (std::size_t i = 0; i < n; ++i) p.emplace_back(1e-3 * static_cast<double>(i), -2e-3, z0 + 1e-3 * static_cast<double>(i));
    return p;
}

/// One snapshot group, as run_command.cpp's write_snapshot writes it.
void write_snapshot(Group g, const Sizes& n, double strain, double time_s)
{
    g.write_double_attribute("requested_axial_strain", strain);
    g.write_double_attribute("axial_strain", strain + 1e-6);
    g.write_double_attribute("time_s", time_s);
    units(g.write_dataset("grain_position_m", points(n.grains, 0.0)), "m");
    units(g.write_dataset("grain_radius_m", std::vector<double>(n.grains, 1.2e-3)), "m");
    units(g.write_dataset("grain_velocity_m_per_s", points(n.grains, 0.5)), "m/s");
    units(g.write_dataset("wire_node_position_m", points(n.wire_nodes, 0.01)), "m");
    std::vector<double> strains;
    for (std::size_t s = 0; s + 1 < n.wire_nodes; ++s) strains.push_back(1e-3 * static_cast<double>(s));
    units(g.write_dataset("wire_segment_strain", strains), "1");
    units(g.write_dataset("membrane_node_position_m", points(n.membrane_nodes, 0.02)), "m");
    const std::vector<std::uint32_t> tri = {0, 1, 2, 1, 3, 2, 2, 3, 4, 3, 5, 4};
    units(g.write_dataset("membrane_triangles", std::span<const std::uint32_t>(tri), 3), "1");
    // kind, index, kind, index: grain–grain, grain–wire, grain–membrane, wire–wire
    const std::vector<std::uint32_t> pairs = {0, 0, 0, 1, 0, 1, 0, 4, 0, 2, 1, 3, 0, 4, 2, 5, 1, 0, 1, 2};
    units(g.write_dataset("contact_bodies", std::span<const std::uint32_t>(pairs), 4), "1");
    units(g.write_dataset("contact_force_n", points(5, 1.0)), "N");
    units(g.write_dataset("contact_normal_force_n", std::vector<double>{1.0, 2.0, 3.0, 4.0, 5.0}), "N");
    const std::vector<std::uint32_t> walls = {0, 0, 0};
    units(g.write_dataset("wall_contact_bodies", std::span<const std::uint32_t>(walls), 3), "1");
    units(g.write_dataset("wall_contact_force_n", points(1, 3.0)), "N");
}

/// A result file of the documented layout: specimen, two tests (written in the
/// order 100 kPa, 20 kPa so that byte order and pressure order differ), snapshots.
void write_result(const fs::path& path, const Sizes& n, bool with_tests = true,
    const std::function<void(Group& root)>& more = {})
{
    write_file_atomically(path, [&](Group& root) {
        root.write_string_attribute("format", "wiredem-result-1");
        root.write_string_dataset("job_spec", "{\"name\": \"xdmf test\"}");
        Group sp = root.create_group("specimen");
        sp.write_int_attribute("grains", static_cast<std::int64_t>(n.grains));
        units(sp.write_dataset("grain_position_m", points(n.grains, 0.0)), "m");
        units(sp.write_dataset("grain_radius_m", std::vector<double>(n.grains, 1.2e-3)), "m");
        units(sp.write_dataset("wire_node_position_m", points(n.wire_nodes, 0.01)), "m");
        units(sp.write_dataset("membrane_node_position_m", points(n.membrane_nodes, 0.02)), "m");
        if (with_tests) {
            Group t1 = root.create_group("tests/sigma3_100000");
            t1.write_double_attribute("confining_pressure_pa", 1e5);
            units(t1.write_dataset("time_s", std::vector<double>{0.0, 0.1}), "s");
            for (int k = 0; k < 2; ++k)
                write_snapshot(t1.create_group("snapshots/snapshot_" + std::to_string(k)), n, 0.05 * k, 0.1 * k);
            Group t2 = root.create_group("tests/sigma3_20000");
            t2.write_double_attribute("confining_pressure_pa", 2e4);
            // 11 snapshots: snapshot_10 must come after snapshot_9, not after snapshot_1
            for (int k = 0; k < 11; ++k)
                write_snapshot(t2.create_group("snapshots/snapshot_" + std::to_string(k)), n, 0.01 * k, 0.02 * k);
        }
        if (more) more(root);
    });
}

ptree read_xml(const fs::path& path)
{
    ptree tree;
    boost::property_tree::read_xml(path.string(), tree);
    return tree;
}

std::string attr(const ptree& node, const std::string& name, const std::string& fallback = "")
{
    return node.get<std::string>("<xmlattr>." + name, fallback);
}

std::vector<std::size_t> numbers(const std::string& text)
{
    std::istringstream in(text);
    std::vector<std::size_t> v;
    long long x = 0;
    while (in >> x) v.push_back(static_cast<std::size_t>(x));
    return v;
}

std::size_t product(const std::vector<std::size_t>& dims)
{
    std::size_t p = 1;
    for (const std::size_t d : dims) p *= d;
    return p;
}

/// Calls `visit(name, node, path)` for every element below `node`, depth first.
void walk(const ptree& node, const std::string& path,
    const std::function<void(const std::string&, const ptree&, const std::string&)>& visit)
{
    for (const auto& [name, child] : node) {
        if (name == "<xmlattr>" || name == "<xmlcomment>") continue;
        visit(name, child, path + "/" + name);
        walk(child, path + "/" + name, visit);
    }
}

/// The XDMF NumberType and Precision of a stored dataset.
std::pair<std::string, std::string> stored_type(const Dataset& ds)
{
    const hid_t type = H5Dget_type(ds.id());
    const H5T_class_t cls = H5Tget_class(type);
    const std::size_t size = H5Tget_size(type);
    const bool is_unsigned = cls == H5T_INTEGER && H5Tget_sign(type) == H5T_SGN_NONE;
    H5Tclose(type);
    const std::string name = cls == H5T_FLOAT ? "Float" : is_unsigned ? "UInt" : "Int";
    return {name, std::to_string(size)};
}

/// Rows of an array DataItem (first dimension).
std::size_t item_rows(const ptree& item) { return numbers(attr(item, "Dimensions")).at(0); }

/// The values of an inline (Format="XML") integer DataItem.
std::vector<std::size_t> inline_values(const ptree& item)
{
    EXPECT_EQ(attr(item, "Format"), "XML");
    EXPECT_EQ(attr(item, "NumberType"), "Int");
    return numbers(item.get_value<std::string>());
}

/// The values of any inline (Format="XML") DataItem.
std::vector<double> inline_doubles(const ptree& item)
{
    EXPECT_EQ(attr(item, "Format"), "XML");
    std::istringstream in(item.get_value<std::string>());
    std::vector<double> v;
    double x = 0;
    while (in >> x) v.push_back(x);
    EXPECT_TRUE(in.eof()) << "not a number in an inline DataItem";
    return v;
}

/// Uniform grids by (enclosing collection names + own name), e.g. "sigma3_20000/snapshot_3/wire".
std::map<std::string, const ptree*> uniform_grids(const ptree& domain)
{
    std::map<std::string, const ptree*> grids;
    std::function<void(const ptree&, const std::string&)> visit = [&](const ptree& node, const std::string& prefix) {
        for (const auto& [name, child] : node) {
            if (name != "Grid") continue;
            const std::string key = prefix + attr(child, "Name");
            if (attr(child, "GridType") == "Collection")
                visit(child, key + "/");
            else
                grids[key] = &child;
        }
    };
    visit(domain, "");
    return grids;
}

const ptree& data_item_of(const ptree& parent) { return parent.get_child("DataItem"); }

} // namespace

TEST(XdmfSidecar, EveryHdfDataItemNamesAnExistingDatasetWithItsDimensionsAndType)
{
    const TempDir dir;
    const fs::path h5 = dir.path() / "result.h5";
    write_result(h5, Sizes{});
    const XdmfSummary s = write_xdmf(h5);
    const fs::path xdmf = dir.path() / "result.xdmf";
    ASSERT_TRUE(fs::exists(xdmf));
    EXPECT_FALSE(fs::exists(dir.path() / "result.xdmf.partial"));
    EXPECT_TRUE(s.specimen);
    EXPECT_EQ(s.tests, 2u);
    EXPECT_EQ(s.snapshots, 13u);
    EXPECT_EQ(s.grids, 3u + 13u * 4u); // specimen: grains, wire, membrane; snapshots: + contacts

    const ptree tree = read_xml(xdmf);
    EXPECT_EQ(attr(tree.get_child("Xdmf"), "Version"), "3.0");
    const File file = File::open_read_only(h5);
    const Group root = file.root();
    std::size_t hdf_items = 0, inline_items = 0;
    walk(tree, "", [&](const std::string& name, const ptree& node, const std::string& where) {
        if (name != "DataItem") return;
        const std::vector<std::size_t> dims = numbers(attr(node, "Dimensions"));
        ASSERT_FALSE(dims.empty()) << where;
        EXPECT_EQ(attr(node, "ItemType", "Uniform"), "Uniform") << where; // ParaView evaluates no functions
        const std::string format = attr(node, "Format");
        if (format == "XML") {
            ++inline_items;
            EXPECT_EQ(inline_doubles(node).size(), product(dims)) << where;
            return;
        }
        ASSERT_EQ(format, "HDF") << where;
        ++hdf_items;
        std::string text = node.get_value<std::string>();
        const std::size_t colon = text.find(':');
        ASSERT_NE(colon, std::string::npos) << text;
        EXPECT_EQ(text.substr(0, colon), "result.h5") << "relative to the XDMF file";
        const std::string path = text.substr(colon + 1);
        ASSERT_TRUE(root.exists(path)) << path;
        const Dataset ds = root.open_dataset(path);
        EXPECT_EQ(ds.shape(), dims) << path;
        const auto [type, precision] = stored_type(ds);
        EXPECT_EQ(attr(node, "NumberType"), type) << path;
        EXPECT_EQ(attr(node, "Precision"), precision) << path;
    });
    // specimen: 3 geometries, radius, borrowed triangles; per snapshot: grains 3, wire 2,
    // membrane 2, contacts 2 attributes
    EXPECT_EQ(hdf_items, 5u + 13u * 9u);
    // specimen: grain vertices, wire segments; per snapshot: the same + contact ends and points
    EXPECT_EQ(inline_items, 2u + 13u * 4u);
}

TEST(XdmfSidecar, TopologySizesMatchGeometryAndAttributes)
{
    const TempDir dir;
    const fs::path h5 = dir.path() / "result.h5";
    write_result(h5, Sizes{});
    write_xdmf(h5);
    const ptree tree = read_xml(dir.path() / "result.xdmf");
    const auto grids = uniform_grids(tree.get_child("Xdmf.Domain"));
    ASSERT_EQ(grids.size(), 3u + 13u * 4u);
    for (const auto& [key, grid] : grids) {
        const ptree& topo = grid->get_child("Topology");
        // Init-captures: clang 14 cannot capture a structured binding itself.
        const std::size_t nodes = [&key = key, &grid = grid] {
            const ptree& item = data_item_of(grid->get_child("Geometry"));
            EXPECT_EQ(numbers(attr(item, "Dimensions")).at(1), 3u) << key;
            EXPECT_EQ(attr(grid->get_child("Geometry"), "GeometryType"), "XYZ") << key;
            return item_rows(item);
        }();
        const std::string type = attr(topo, "TopologyType");
        const std::size_t cells = std::stoul(attr(topo, "NumberOfElements"));
        const std::size_t per_cell = std::stoul(attr(topo, "NodesPerElement"));
        if (type == "Polyvertex") {
            EXPECT_EQ(cells, nodes) << key;
            EXPECT_EQ(per_cell, 1u) << key;
        } else {
            ASSERT_TRUE(type == "Polyline" || type == "Triangle") << key << ": " << type;
            EXPECT_EQ(per_cell, type == "Triangle" ? 3u : 2u) << key;
            const ptree& conn = data_item_of(topo);
            EXPECT_EQ(numbers(attr(conn, "Dimensions")), (std::vector<std::size_t>{cells, per_cell})) << key;
            if (attr(conn, "Format") == "XML") {
                for (const std::size_t v : inline_values(conn)) EXPECT_LT(v, nodes) << key;
            }
        }
        if (type == "Polyvertex") { // one vertex cell per node, in order
            const std::vector<std::size_t> v = inline_values(data_item_of(topo));
            ASSERT_EQ(v.size(), nodes) << key;
            for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(v[i], i) << key;
        }
        for (const auto& [name, child] : *grid) {
            if (name != "Attribute") continue;
            const std::size_t rows = item_rows(data_item_of(child));
            EXPECT_EQ(rows, attr(child, "Center") == "Cell" ? cells : nodes) << key << " " << attr(child, "Name");
        }
    }
    // the membrane of the specimen borrows the snapshots' triangles
    EXPECT_EQ(attr(grids.at("specimen/membrane")->get_child("Topology"), "TopologyType"), "Triangle");
    // grains are spheres: radius everywhere, velocity in snapshots
    EXPECT_EQ(attr(grids.at("specimen/grains")->get_child("Attribute"), "Name"), "radius_m");
    int velocity = 0;
    for (const auto& [name, child] : *grids.at("sigma3_20000/snapshot_0/grains"))
        if (name == "Attribute" && attr(child, "Name") == "velocity_m_per_s") ++velocity;
    EXPECT_EQ(velocity, 1);
}

TEST(XdmfSidecar, ClumpsSpheresAreGrainsWithTheirClumpsIndex)
{
    // A result of clumps (docs/results.md): every sphere is a grain vertex with
    // its radius, and grain_clump (an integer per sphere, −1 for a free grain)
    // becomes the grains' `clump` attribute; without it there is none.
    const TempDir dir;
    const fs::path h5 = dir.path() / "result.h5";
    write_result(h5, Sizes{}, false);
    {
        const File f = File::open_read_write(h5);
        units(f.root().open_group("specimen").write_dataset("grain_clump", std::vector<std::int64_t>{0, 0, 1, 1, -1}), "1");
    }
    write_xdmf(h5);
    const ptree tree = read_xml(dir.path() / "result.xdmf");
    const auto grids = uniform_grids(tree.get_child("Xdmf.Domain"));
    std::vector<std::string> names;
    for (const auto& [name, child] : *grids.at("specimen/grains"))
        if (name == "Attribute") {
            names.push_back(attr(child, "Name"));
            if (attr(child, "Name") == "clump") {
                const ptree& item = data_item_of(child);
                EXPECT_EQ(item_rows(item), 5u);
                EXPECT_EQ(attr(item, "NumberType"), "Int");
            }
        }
    EXPECT_EQ(names, (std::vector<std::string>{"radius_m", "clump"}));
}

TEST(XdmfSidecar, WireIsAPolylineOfNodesMinusOneSegmentsWithTheirStrain)
{
    const TempDir dir;
    const fs::path h5 = dir.path() / "result.h5";
    Sizes n;
    n.wire_nodes = 9;
    write_result(h5, n);
    write_xdmf(h5);
    const ptree tree = read_xml(dir.path() / "result.xdmf");
    const auto grids = uniform_grids(tree.get_child("Xdmf.Domain"));
    for (const std::string key : {"specimen/wire", "sigma3_100000/snapshot_1/wire"}) {
        const ptree& topo = grids.at(key)->get_child("Topology");
        EXPECT_EQ(attr(topo, "TopologyType"), "Polyline") << key;
        EXPECT_EQ(attr(topo, "NumberOfElements"), "8") << key;
        const std::vector<std::size_t> v = inline_values(data_item_of(topo));
        ASSERT_EQ(v.size(), 16u);
        for (std::size_t s = 0; s < 8; ++s) {
            EXPECT_EQ(v[2 * s], s);
            EXPECT_EQ(v[2 * s + 1], s + 1);
        }
    }
    const ptree& strain = grids.at("sigma3_100000/snapshot_1/wire")->get_child("Attribute");
    EXPECT_EQ(attr(strain, "Name"), "segment_strain");
    EXPECT_EQ(attr(strain, "Center"), "Cell");
    EXPECT_EQ(data_item_of(strain).get_value<std::string>(), "result.h5:/tests/sigma3_100000/snapshots/snapshot_1/wire_segment_strain");
}

// A cut or broken wire is drawn as it was: the specimen without the segments
// removed in the preparation, each snapshot also without those its test broke
// by then (wire_breaks' time_s, the test's clock, as the snapshot's), the
// remaining segments' strain beside them.
TEST(XdmfSidecar, ACutOrBrokenWireHasNoSegmentWhereItWasCutOrBroke)
{
    const TempDir dir;
    const fs::path h5 = dir.path() / "result.h5";
    Sizes n;
    n.wire_nodes = 9; // segments 0 … 7
    const auto breaks = [](Group g, std::vector<std::int64_t> segment, std::vector<double> time_s) {
        Group b = g.create_group("wire_breaks");
        b.write_dataset("segment", std::span<const std::int64_t>(segment));
        b.write_dataset("time_s", std::span<const double>(time_s));
    };
    write_result(h5, n, true, [&](Group& root) {
        breaks(root.open_group("specimen"), {2}, {0.5});
        breaks(root.open_group("tests/sigma3_100000"), {5}, {0.05}); // between its snapshots at 0 and 0.1 s
    });
    write_xdmf(h5);
    const ptree tree = read_xml(dir.path() / "result.xdmf");
    const auto grids = uniform_grids(tree.get_child("Xdmf.Domain"));
    const auto segments = [&](const std::string& key) {
        const ptree& topo = grids.at(key)->get_child("Topology");
        const std::vector<std::size_t> v = inline_values(data_item_of(topo));
        EXPECT_EQ(std::to_string(v.size() / 2), attr(topo, "NumberOfElements")) << key;
        std::vector<std::size_t> first;
        for (std::size_t i = 0; i + 1 < v.size(); i += 2) {
            EXPECT_EQ(v[i + 1], v[i] + 1) << key;
            first.push_back(v[i]);
        }
        return first;
    };
    EXPECT_EQ(segments("specimen/wire"), (std::vector<std::size_t>{0, 1, 3, 4, 5, 6, 7}));
    EXPECT_EQ(segments("sigma3_100000/snapshot_0/wire"), (std::vector<std::size_t>{0, 1, 3, 4, 5, 6, 7}));
    EXPECT_EQ(segments("sigma3_100000/snapshot_1/wire"), (std::vector<std::size_t>{0, 1, 3, 4, 6, 7}));
    EXPECT_EQ(segments("sigma3_20000/snapshot_10/wire"), (std::vector<std::size_t>{0, 1, 3, 4, 5, 6, 7}));
    // The strain of the segments drawn, in their order (write_snapshot: 1e-3 s).
    const ptree& strain = grids.at("sigma3_100000/snapshot_1/wire")->get_child("Attribute");
    EXPECT_EQ(attr(strain, "Center"), "Cell");
    const std::vector<double> e = inline_doubles(data_item_of(strain));
    ASSERT_EQ(e.size(), 6u);
    const std::vector<double> drawn{0, 1, 3, 4, 6, 7};
    for (std::size_t i = 0; i < e.size(); ++i) EXPECT_EQ(e[i], 1e-3 * drawn[i]) << i;
}

TEST(XdmfSidecar, ForceNetworkJoinsTheRightBodies)
{
    const TempDir dir;
    const fs::path h5 = dir.path() / "result.h5";
    write_result(h5, Sizes{});
    write_xdmf(h5);
    const ptree tree = read_xml(dir.path() / "result.xdmf");
    const auto grids = uniform_grids(tree.get_child("Xdmf.Domain"));
    const ptree& contacts = *grids.at("sigma3_20000/snapshot_10/contacts");
    EXPECT_EQ(attr(contacts.get_child("Topology"), "NumberOfElements"), "5");
    EXPECT_EQ(inline_values(data_item_of(contacts.get_child("Topology"))),
        (std::vector<std::size_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
    // (g0,g1) (g1,g4) (g2,w3) (g4,m5) (w0,w2): each end at its body's stored position
    const File file = File::open_read_only(h5);
    const Group snap = file.root().open_group("tests/sigma3_20000/snapshots/snapshot_10");
    const std::vector<std::vector<double>> pos = {snap.open_dataset("grain_position_m").read_doubles(),
        snap.open_dataset("wire_node_position_m").read_doubles(),
        snap.open_dataset("membrane_node_position_m").read_doubles()};
    const std::vector<std::pair<int, int>> ends = {{0, 0}, {0, 1}, {0, 1}, {0, 4}, {0, 2}, {1, 3}, {0, 4}, {2, 5}, {1, 0}, {1, 2}};
    const std::vector<double> xyz = inline_doubles(data_item_of(contacts.get_child("Geometry")));
    ASSERT_EQ(xyz.size(), 3 * ends.size());
    for (std::size_t e = 0; e < ends.size(); ++e)
        for (std::size_t d = 0; d < 3; ++d)
            EXPECT_NEAR(xyz[3 * e + d], pos[ends[e].first][3 * ends[e].second + d], 1e-12) << "end " << e;
    std::vector<std::string> attributes;
    for (const auto& [name, child] : contacts)
        if (name == "Attribute") attributes.push_back(attr(child, "Name") + ":" + attr(child, "Center"));
    EXPECT_EQ(attributes, (std::vector<std::string>{"normal_force_n:Cell", "force_n:Cell"}));
}

TEST(XdmfSidecar, EachTestIsATemporalCollectionInPressureOrderTimedByRequestedStrain)
{
    const TempDir dir;
    const fs::path h5 = dir.path() / "result.h5";
    write_result(h5, Sizes{});
    write_xdmf(h5);
    const ptree tree = read_xml(dir.path() / "result.xdmf");
    std::vector<std::string> names;
    std::vector<std::vector<double>> times;
    std::vector<std::vector<std::string>> steps;
    for (const auto& [name, grid] : tree.get_child("Xdmf.Domain")) {
        if (name != "Grid") continue;
        names.push_back(attr(grid, "Name"));
        if (attr(grid, "CollectionType") != "Temporal") {
            EXPECT_EQ(attr(grid, "Name"), "specimen");
            EXPECT_EQ(attr(grid, "CollectionType"), "Spatial");
            continue;
        }
        times.emplace_back();
        steps.emplace_back();
        for (const auto& [child_name, step] : grid) {
            if (child_name != "Grid") continue;
            times.back().push_back(std::stod(attr(step.get_child("Time"), "Value")));
            steps.back().push_back(attr(step, "Name"));
        }
    }
    EXPECT_EQ(names, (std::vector<std::string>{"specimen", "sigma3_20000", "sigma3_100000"}));
    ASSERT_EQ(times.size(), 2u);
    ASSERT_EQ(times[0].size(), 11u);
    for (std::size_t k = 0; k < 11; ++k) {
        EXPECT_DOUBLE_EQ(times[0][k], 0.01 * static_cast<double>(k)); // the requested strain
        EXPECT_EQ(steps[0][k], "snapshot_" + std::to_string(k));
    }
    EXPECT_EQ(times[1].size(), 2u);
}

TEST(XdmfSidecar, ReferencesTheHdf5FileRelativeToTheSidecar)
{
    const TempDir dir;
    fs::create_directories(dir.path() / "data");
    fs::create_directories(dir.path() / "views");
    const fs::path h5 = dir.path() / "data" / "run.h5";
    write_result(h5, Sizes{}, false);
    const XdmfSummary s = write_xdmf(h5, dir.path() / "views" / "run.xdmf");
    EXPECT_EQ(s.tests, 0u);
    EXPECT_EQ(s.grids, 3u);
    const ptree tree = read_xml(dir.path() / "views" / "run.xdmf");
    std::size_t items = 0;
    walk(tree, "", [&](const std::string& name, const ptree& node, const std::string&) {
        if (name == "DataItem" && attr(node, "Format") == "HDF") {
            EXPECT_EQ(node.get_value<std::string>().rfind("../data/run.h5:/specimen/", 0), 0u) << node.get_value<std::string>();
            ++items;
        }
    });
    EXPECT_EQ(items, 4u);
    // without snapshots the membrane has no triangles: its nodes are shown as points
    const auto grids = uniform_grids(tree.get_child("Xdmf.Domain"));
    EXPECT_EQ(attr(grids.at("specimen/membrane")->get_child("Topology"), "TopologyType"), "Polyvertex");
}

TEST(XdmfSidecar, WithoutWireThereIsNoWireGrid)
{
    const TempDir dir;
    const fs::path h5 = dir.path() / "result.h5";
    Sizes n;
    n.wire_nodes = 0;
    write_file_atomically(h5, [&](Group& root) {
        Group sp = root.create_group("specimen");
        sp.write_dataset("grain_position_m", points(n.grains, 0.0));
        sp.write_dataset("grain_radius_m", std::vector<double>(n.grains, 1e-3));
        sp.write_dataset("wire_node_position_m", std::span<const Vec3>{});
        sp.write_dataset("membrane_node_position_m", std::span<const Vec3>{});
    });
    const XdmfSummary s = write_xdmf(h5);
    EXPECT_EQ(s.grids, 1u);
    const ptree tree = read_xml(dir.path() / "result.xdmf");
    const auto grids = uniform_grids(tree.get_child("Xdmf.Domain"));
    EXPECT_EQ(grids.size(), 1u);
    EXPECT_EQ(grids.count("specimen/grains"), 1u);
}

TEST(XdmfSidecar, MissingResultFileThrowsAndLeavesNoSidecar)
{
    const TempDir dir;
    EXPECT_THROW(write_xdmf(dir.path() / "absent.h5"), Hdf5Error);
    EXPECT_FALSE(fs::exists(dir.path() / "absent.xdmf"));
    EXPECT_FALSE(fs::exists(dir.path() / "absent.xdmf.partial"));
}

#ifdef WIREDEM_BIN
TEST(XdmfSidecar, ExportCommandWritesTheSidecarNextToTheResult)
{
    const TempDir dir;
    const fs::path h5 = dir.path() / "result.h5";
    write_result(h5, Sizes{});
    const std::string cmd = std::string(WIREDEM_BIN) + " export-xdmf '" + h5.string() + "' > '"
                          + (dir.path() / "out.txt").string() + "' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    EXPECT_TRUE(fs::exists(dir.path() / "result.xdmf"));
    std::ifstream in(dir.path() / "out.txt");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("2 test(s), 13 snapshot(s)"), std::string::npos) << text;
    // a missing file is a local I/O error (exit 9)
    const std::string bad = std::string(WIREDEM_BIN) + " export-xdmf '" + (dir.path() / "nope.h5").string() + "' 2>/dev/null";
    const int rc = std::system(bad.c_str());
    ASSERT_TRUE(WIFEXITED(rc));
    EXPECT_EQ(WEXITSTATUS(rc), 9);
}

// `wiredem autocorrelation` (client/autocorrelation_command.cpp): the server
// route's reply (api::wire_autocorrelation_json) for a file's snapshot, with
// the segment length of the file's job; by default the highest pressure's last.
TEST(AutocorrelationCommand, AnswersWhatTheServerRouteAnswersForASnapshot)
{
    const TempDir dir;
    const fs::path h5 = dir.path() / "result.h5";
    const Sizes n{5, 9, 6};
    write_result(h5, n);
    const auto run = [&](const std::string& args) {
        const fs::path out = dir.path() / "out.txt";
        const std::string cmd = std::string(WIREDEM_BIN) + " autocorrelation '" + h5.string() + "' " + args + " > '"
                              + out.string() + "' 2>&1";
        const int rc = std::system(cmd.c_str());
        std::ifstream in(out);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        while (!text.empty() && text.back() == '\n') text.pop_back();
        return std::pair{WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, text};
    };
    std::vector<double> strains;  // write_snapshot's: 1e-3 s for segment s
    for (std::size_t s = 0; s + 1 < n.wire_nodes; ++s) strains.push_back(1e-3 * static_cast<double>(s));
    const double segment_m = wiredem::api::parse_job_spec(R"({"name": "xdmf test"})").value().specimen.wire.segment_length_m;
    const std::string expected = boost::json::serialize(wiredem::api::wire_autocorrelation_json(strains, segment_m));
    EXPECT_EQ(run(""), std::pair(0, expected));  // sigma3_100000, the highest pressure: its last, snapshot_1
    EXPECT_EQ(run("--test sigma3_20000 --snapshot 10"), std::pair(0, expected));
    EXPECT_EQ(run("--snapshot 2").first, 9);  // sigma3_100000 has snapshots 0 and 1
    EXPECT_EQ(run("--test sigma3_1").first, 9);
    EXPECT_EQ(run("--snapshot -1").first, 2);
}
#endif

TEST(XdmfSidecar, ParaViewReadsEveryGridWithItsSizes)
{
    const char* pvpython = "/usr/bin/pvpython";
    if (!fs::exists(pvpython)) GTEST_SKIP() << "ParaView (pvpython) not installed";
    const TempDir dir;
    const fs::path h5 = dir.path() / "result.h5";
    write_result(h5, Sizes{});
    write_xdmf(h5);
    // Prints "BLOCK name points cells arrays" per data set at the last time (reader T:
    // one block per top-level grid, named blocks inside).
    const fs::path script = dir.path() / "read.py";
    {
        std::ofstream py(script);
        py << "from paraview.simple import *\n"
              "from paraview import servermanager as sm\n"
              "r = Xdmf3ReaderT(FileName=['" << (dir.path() / "result.xdmf").string() << "'])\n"
              "print('TIMES', len(r.TimestepValues))\n"
              "r.UpdatePipeline(max(r.TimestepValues))\n"
              "def walk(o, name):\n"
              "    if o is None: return\n"
              "    if o.IsA('vtkMultiBlockDataSet'):\n"
              "        for i in range(o.GetNumberOfBlocks()):\n"
              "            md = o.GetMetaData(i) if o.HasMetaData(i) else None\n"
              "            walk(o.GetBlock(i), md.Get(o.NAME()) if md is not None and md.Has(o.NAME()) else '?')\n"
              "    elif o.IsA('vtkMultiPieceDataSet'):\n"
              "        for i in range(o.GetNumberOfPieces()): walk(o.GetPiece(i), name)\n"
              "    else:\n"
              "        print('BLOCK', name.split('[')[0], o.GetNumberOfPoints(), o.GetNumberOfCells(),\n"
              "              o.GetPointData().GetNumberOfArrays() + o.GetCellData().GetNumberOfArrays())\n"
              "walk(sm.Fetch(r), '?')\n";
    }
    const fs::path out = dir.path() / "out.txt";
    const std::string cmd = std::string(pvpython) + " --force-offscreen-rendering '" + script.string() + "' > '"
                          + out.string() + "' 2>&1";
    const int rc = std::system(cmd.c_str());
    std::ifstream in(out);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_EQ(rc, 0) << text;
    // the 11 strains of the 20 kPa test; the 100 kPa test's two are among them
    EXPECT_NE(text.find("TIMES 11"), std::string::npos) << text;
    // grains 5 points 5 vertices, 2 arrays; wire 4 points 3 segments, 1 array;
    // membrane 6 points 4 triangles; contacts 10 end points 5 segments, 2 arrays
    EXPECT_NE(text.find("BLOCK grains 5 5 2"), std::string::npos) << text;
    EXPECT_NE(text.find("BLOCK wire 4 3 1"), std::string::npos) << text;
    EXPECT_NE(text.find("BLOCK membrane 6 4 0"), std::string::npos) << text;
    EXPECT_NE(text.find("BLOCK contacts 10 5 2"), std::string::npos) << text;
}
