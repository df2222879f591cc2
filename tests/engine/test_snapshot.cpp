// A snapshot restores a run so that it continues bit-identically, in this
// process or a fresh one, with any thread count; its errors are messages.
#include "io/hdf5.hpp"
#include "io/snapshot.hpp"
#include "simulation.hpp"
#include "state/state_hash.hpp"
#include "timestep.hpp"
#include "triaxial/cuboid.hpp"
#include "wired_column.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <optional>
#include <span>
#include <string>
#include <unistd.h>

using namespace wiredem::engine;
using wiredem::engine::test::build_wired_column;

namespace {

/// Steps before the snapshot and after it.
constexpr std::uint64_t steps_before = 900, steps_after = 400;

/// A fresh path in the test's temporary directory.
std::filesystem::path temp_path(const std::string& name)
{
    return std::filesystem::temp_directory_path() / ("wiredem_test_snapshot_" + std::to_string(::getpid()) + "_" + name);
}

/// Builds the wired column in `sim` and runs it `steps_before` steps.
void run_column_to_mid_test(Simulation& sim, Integrator integrator)
{
    build_wired_column(sim.world, integrator);
    ASSERT_EQ(sim.run(steps_before).end, RunEnd::completed);
}

/// What makes the column a hard case at the snapshot: plates moving and
/// pressed, pair and wall contacts sliding, yielded wire joints, a membrane
/// that has moved.
void expect_mid_test(const World& w)
{
    const ContactList& c = w.contacts;
    std::size_t sliding_pairs = 0, touching_pairs = 0;
    for (std::size_t p = 0; p < c.pair_count(); ++p) {
        touching_pairs += c.touching[p];
        sliding_pairs += c.touching[p] && !c.tangential[p].sticking;
    }
    EXPECT_GT(touching_pairs, 100u);
    EXPECT_GT(sliding_pairs, 0u);
    std::size_t sliding_on_walls = 0;
    for (std::size_t p = c.pair_count(); p < c.size(); ++p) sliding_on_walls += c.touching[p] && !c.tangential[p].sticking;
    EXPECT_GT(sliding_on_walls, 0u);
    EXPECT_GT(w.wall_loads[1].contacts, 0u) << "the moving top plate presses on the grains";
    EXPECT_NE(w.walls[1].velocity_m_per_s.z(), 0.0);
    double max_rest_angle = 0.0;
    for (double a : w.wire_rest_angle_rad) max_rest_angle = std::max(max_rest_angle, a);
    EXPECT_GT(max_rest_angle, 0.0) << "some joints have yielded";
    EXPECT_FALSE(w.membrane.rigid);
}

class SnapshotRoundTrip : public ::testing::TestWithParam<Integrator> {};

} // namespace

TEST_P(SnapshotRoundTrip, ContinuesBitIdenticallyInThisProcess)
{
    Simulation original(2);
    ASSERT_NO_FATAL_FAILURE(run_column_to_mid_test(original, GetParam()));
    expect_mid_test(original.world);
    const std::filesystem::path path = temp_path("in_process.h5");
    const auto saved = save_snapshot(original.world, path);
    ASSERT_TRUE(saved.ok()) << saved.error();
    EXPECT_EQ(saved.value(), state_hash(original.world));

    auto restored = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_TRUE(restored.ok()) << restored.error();
    Simulation resumed(3); // another thread count: results do not depend on it
    resumed.world = std::move(restored).value();
    EXPECT_EQ(state_hash(resumed.world), saved.value());

    // Compared every 100 steps: a run whose neighbour list was rebuilt at
    // another step hashes differently until both lists are rebuilt at the same
    // step again (seen: equal again 400 steps after a forced rebuild on restore).
    for (std::uint64_t done = 0; done < steps_after; done += 100) {
        const RunOutcome a = original.run(100), b = resumed.run(100);
        ASSERT_EQ(a.end, RunEnd::completed) << "after " << done << " + " << a.steps << " steps";
        ASSERT_EQ(b.end, RunEnd::completed) << "after " << done << " + " << b.steps << " steps";
        ASSERT_EQ(state_hash(resumed.world), state_hash(original.world)) << "after " << done + 100 << " steps";
        ASSERT_EQ(resumed.world.neighbour_builds, original.world.neighbour_builds);
        ASSERT_EQ(resumed.world.wall_loads[1].total_force_n, original.world.wall_loads[1].total_force_n);
    }
    EXPECT_EQ(resumed.world.step_count, steps_before + steps_after);
}

/// The second half of ContinuesBitIdenticallyInAFreshProcess, run by it in a
/// child process: restores WIREDEM_SNAPSHOT, runs steps_after steps and writes
/// the state hash to WIREDEM_SNAPSHOT.hash. Disabled: ctest never runs it alone.
TEST(SnapshotChild, DISABLED_RestoreAndContinue)
{
    const char* path = std::getenv("WIREDEM_SNAPSHOT");
    ASSERT_NE(path, nullptr);
    auto restored = restore_snapshot(path);
    ASSERT_TRUE(restored.ok()) << restored.error();
    Simulation resumed(1);
    resumed.world = std::move(restored).value();
    resumed.run(steps_after);
    std::ofstream(std::string(path) + ".hash") << state_hash(resumed.world);
}

TEST_P(SnapshotRoundTrip, ContinuesBitIdenticallyInAFreshProcess)
{
    Simulation original(2);
    ASSERT_NO_FATAL_FAILURE(run_column_to_mid_test(original, GetParam()));
    const std::filesystem::path path = temp_path("fresh_process.h5");
    ASSERT_TRUE(save_snapshot(original.world, path).ok());
    original.run(steps_after);

    const std::string command = "WIREDEM_SNAPSHOT='" + path.string() + "' " + std::filesystem::read_symlink("/proc/self/exe").string()
                              + " --gtest_also_run_disabled_tests --gtest_filter=SnapshotChild.* > /dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    std::uint64_t child_hash = 0;
    std::ifstream(path.string() + ".hash") >> child_hash;
    std::filesystem::remove(path);
    std::filesystem::remove(path.string() + ".hash");
    EXPECT_EQ(child_hash, state_hash(original.world));
}

INSTANTIATE_TEST_SUITE_P(BothIntegrators, SnapshotRoundTrip, ::testing::Values(Integrator::gear5, Integrator::verlet),
    [](const auto& info) { return info.param == Integrator::gear5 ? "gear5" : "verlet"; });

TEST(Snapshot, MissingFileIsAnError)
{
    const auto r = restore_snapshot(temp_path("does_not_exist.h5"));
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("no such file"), std::string::npos) << r.error();
}

TEST(Snapshot, AnotherHdf5FileIsNotASnapshot)
{
    const std::filesystem::path path = temp_path("other.h5");
    io::File::create(path).root().write_int_attribute("version", snapshot_version);
    const auto r = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("not a wiredem snapshot"), std::string::npos) << r.error();
}

TEST(Snapshot, AnotherVersionIsAnError)
{
    World w;
    build_wired_column(w, Integrator::gear5);
    const std::filesystem::path path = temp_path("version.h5");
    ASSERT_TRUE(save_snapshot(w, path).ok());
    io::File::open_read_write(path).root().write_int_attribute("version", snapshot_version + 1);
    const auto r = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("version " + std::to_string(snapshot_version + 1)), std::string::npos) << r.error();
}

TEST(Snapshot, AWallsOwnFrictionRestoresAndItsRunContinuesBitIdentically)
{
    // Grains sliding in a cuboid of frictionless and frictional walls
    // (Wall::friction_coeff): the snapshot keeps each wall's μ_w (or its
    // absence), and the restored run goes on with the same bits.
    Simulation original(1);
    World& w = original.world;
    const std::uint8_t grain = add_material(w, Material{1e9, 0.3, 7800.0});
    const std::uint8_t plate = add_material(w, Material{1e9, 0.3, 7800.0});
    const CuboidWalls walls = add_cuboid_walls(w, Vec3(-4e-3, -4e-3, 0.0), Vec3(4e-3, 4e-3, 8e-3), plate, 0.0);
    w.walls[walls.lateral[1]].friction_coeff = 0.2;
    w.walls[walls.lateral[3]].friction_coeff = std::nullopt;
    w.contact.normal_damping_s = 1e-5;
    // A 2 × 2 × 2 block in the corners, 10 µm off the lateral walls, thrown at them.
    for (int i = 0; i < 8; ++i) {
        const double x = i % 2 ? 2.79e-3 : -2.79e-3, y = i / 2 % 2 ? 2.79e-3 : -2.79e-3;
        add_grain(w, Vec3(x, y, i / 4 ? 4.3e-3 : 1.19e-3), 1.2e-3, grain, Vec3(100 * x, 50 * y, -0.1));
    }
    set_time_step(w, stable_time_step(w).auto_s);
    std::array<std::size_t, 6> touched{};
    for (int n = 0; n < 300; ++n) {
        ASSERT_FALSE(original.step().blew_up);
        for (std::size_t i = 0; i < 6; ++i) touched[i] += w.wall_loads[i].contacts;
    }
    for (const std::size_t i : {walls.bottom, walls.lateral[0], walls.lateral[1], walls.lateral[2], walls.lateral[3]})
        EXPECT_GT(touched[i], 0u) << "wall " << i; // the top one is far

    const std::filesystem::path path = temp_path("wall_friction.h5");
    ASSERT_TRUE(save_snapshot(w, path).ok());
    auto restored = restore_snapshot(path);
    ASSERT_TRUE(restored.ok()) << restored.error();
    Simulation resumed(2);
    resumed.world = std::move(restored).value();
    for (std::size_t i = 0; i < w.walls.size(); ++i)
        EXPECT_EQ(resumed.world.walls[i].friction_coeff, w.walls[i].friction_coeff) << "wall " << i;
    ASSERT_EQ(original.run(300).end, RunEnd::completed);
    ASSERT_EQ(resumed.run(300).end, RunEnd::completed);
    EXPECT_EQ(state_hash(resumed.world), state_hash(original.world));

    // A version 7 file has no wall friction: every wall has the contact
    // law's (the reader leaves the datasets of this one alone).
    io::File::open_read_write(path).root().write_int_attribute("version", 7);
    auto old = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_TRUE(old.ok()) << old.error();
    for (const Wall& wall : old.value().walls) EXPECT_FALSE(wall.friction_coeff.has_value());
}

TEST(Snapshot, AVersionThreeFileKeepsTheContactOutputsInFourArrays)
{
    // Until version 4 a contact's force, n × F_t, overlap and |F_n| were four
    // datasets. A file of that layout restores into the records; its arrays
    // hold doubled forces here, so that the records must come from them.
    Simulation sim(1);
    build_wired_column(sim.world, Integrator::gear5);
    for (int s = 0; s < 900; ++s) sim.step(); // ~190 pairs and 20 wall contacts touch
    const World& w = sim.world;
    const std::filesystem::path path = temp_path("version3.h5");
    ASSERT_TRUE(save_snapshot(w, path).ok());
    std::vector<Vec3> force, torque_arm;
    std::vector<double> overlap, normal;
    for (const ContactOutput& o : w.contacts.output) {
        force.push_back(2.0 * o.force_n);
        torque_arm.push_back(o.normal_x_tangential_n);
        overlap.push_back(o.overlap_m);
        normal.push_back(o.normal_force_n);
    }
    {
        io::Group root = io::File::open_read_write(path).root();
        root.write_int_attribute("version", 3);
        root.write_dataset("contacts/force_n", std::span<const Vec3>(force));
        root.write_dataset("contacts/normal_x_tangential_n", std::span<const Vec3>(torque_arm));
        root.write_dataset("contacts/overlap_m", std::span<const double>(overlap), 1);
        root.write_dataset("contacts/normal_force_n", std::span<const double>(normal), 1);
    }
    const auto r = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_TRUE(r.ok()) << r.error();
    const ContactList& c = r.value().contacts;
    ASSERT_EQ(c.output.size(), w.contacts.size());
    std::size_t touching = 0;
    for (std::size_t p = 0; p < c.size(); ++p) {
        EXPECT_EQ(c.output[p].force_n, 2.0 * w.contacts.output[p].force_n) << "contact " << p;
        EXPECT_EQ(c.output[p].normal_x_tangential_n, w.contacts.output[p].normal_x_tangential_n);
        EXPECT_EQ(c.output[p].overlap_m, w.contacts.output[p].overlap_m);
        EXPECT_EQ(c.output[p].normal_force_n, w.contacts.output[p].normal_force_n);
        touching += c.touching[p];
    }
    EXPECT_GT(touching, 100u);
    EXPECT_EQ(state_hash(r.value()), state_hash(w));
}

TEST(Snapshot, AVersionFourFileHasItsPairsPutInTheKindsOrder)
{
    // Until version 4 the body pairs were sorted by (first, second) alone: a
    // grain's grain, wire and membrane partners followed each other. Such a
    // list is put in today's order (pair_key), each contact with its memory
    // and outputs, and the run continues as the uninterrupted one does.
    Simulation original(1);
    ASSERT_NO_FATAL_FAILURE(run_column_to_mid_test(original, Integrator::gear5));
    World old = original.world;
    ContactList& c = old.contacts;
    std::vector<std::size_t> order(c.pair_count());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return std::pair(c.first[a].bits, c.second[a].bits) < std::pair(c.first[b].bits, c.second[b].bits);
    });
    ASSERT_FALSE(std::is_sorted(order.begin(), order.end())) << "the column has pairs of several kinds";
    const auto permute = [&](auto& v) {
        auto sorted = v;
        for (std::size_t p = 0; p < order.size(); ++p) sorted[p] = v[order[p]];
        v = std::move(sorted);
    };
    permute(c.first);
    permute(c.second);
    permute(c.hertz_coefficient);
    permute(c.tangential);
    permute(c.output);
    permute(c.touching);
    // (The incidence list is left as it was: a restore indexes the list again.)
    const std::filesystem::path path = temp_path("version4.h5");
    ASSERT_TRUE(save_snapshot(old, path).ok());
    io::File::open_read_write(path).root().write_int_attribute("version", 4);
    auto r = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_TRUE(r.ok()) << r.error();
    const ContactList& restored = r.value().contacts;
    const ContactList& expected = original.world.contacts;
    EXPECT_EQ(restored.first, expected.first);
    EXPECT_EQ(restored.second, expected.second);
    EXPECT_EQ(restored.hertz_coefficient, expected.hertz_coefficient);
    EXPECT_EQ(restored.wall_start, expected.wall_start);
    EXPECT_EQ(restored.incidence_start, expected.incidence_start);
    ASSERT_EQ(restored.incidence.size(), expected.incidence.size());
    for (std::size_t i = 0; i < expected.incidence.size(); ++i)
        ASSERT_EQ(restored.incidence[i].bits, expected.incidence[i].bits) << "incidence " << i;
    for (std::size_t p = 0; p < expected.size(); ++p)
        ASSERT_EQ(restored.output[p].force_n, expected.output[p].force_n) << "contact " << p;
    EXPECT_EQ(state_hash(r.value()), state_hash(original.world)); // springs and touching flags in order

    Simulation resumed(2);
    resumed.world = std::move(r).value();
    original.run(steps_after);
    resumed.run(steps_after);
    EXPECT_EQ(state_hash(resumed.world), state_hash(original.world));
}


TEST(Snapshot, AVersionFiveFileHasItsMembraneElementsPutInGridOrder)
{
    // Until version 5 the membrane's edges were listed by (lower, higher)
    // node, the triangles quad by quad. Such lists are put in grid order, each
    // edge with its rest length, and the run continues as the uninterrupted one does.
    Simulation original(1);
    ASSERT_NO_FATAL_FAILURE(run_column_to_mid_test(original, Integrator::gear5));
    World old = original.world;
    MembraneMesh& m = old.membrane;
    std::vector<std::size_t> order(m.edges.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return std::minmax(m.edges[a][0], m.edges[a][1]) < std::minmax(m.edges[b][0], m.edges[b][1]);
    });
    std::vector<std::array<std::uint32_t, 2>> edges;
    std::vector<double> rest;
    for (const std::size_t e : order) {
        edges.push_back({std::min(m.edges[e][0], m.edges[e][1]), std::max(m.edges[e][0], m.edges[e][1])});
        rest.push_back(m.edge_rest_m[e]);
    }
    ASSERT_NE(edges, m.edges);
    m.edges = edges;
    m.edge_rest_m = rest;
    std::reverse(m.triangles.begin(), m.triangles.end());
    const std::filesystem::path path = temp_path("version5.h5");
    ASSERT_TRUE(save_snapshot(old, path).ok());
    io::File::open_read_write(path).root().write_int_attribute("version", 5);
    auto r = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(r.value().membrane.edges, original.world.membrane.edges);
    EXPECT_EQ(r.value().membrane.edge_rest_m, original.world.membrane.edge_rest_m);
    EXPECT_EQ(r.value().membrane.triangles, original.world.membrane.triangles);

    Simulation resumed(2);
    resumed.world = std::move(r).value();
    original.run(steps_after);
    resumed.run(steps_after);
    EXPECT_EQ(state_hash(resumed.world), state_hash(original.world));
}
TEST(Snapshot, AMissingFieldIsNamed)
{
    const std::filesystem::path path = temp_path("truncated.h5");
    {
        io::File file = io::File::create(path);
        io::Group root = file.root();
        root.write_string_attribute("format", "wiredem snapshot");
        root.write_int_attribute("version", snapshot_version);
        root.write_int_attribute("wall_count", 0);
        root.write_string_attribute("state_hash", "0");
    }
    const auto r = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("field integrator is missing"), std::string::npos) << r.error();
}

TEST(Snapshot, ArraysThatDoNotFitTheBodiesAreRefused)
{
    // A file whose per-body arrays disagree with the bodies (edited, or
    // written by a broken program) is refused, naming the field, before the
    // engine could index past an array's end. The state hash does not cover
    // forces, so only this check stands between such a file and the step.
    Simulation sim(1);
    build_wired_column(sim.world, Integrator::gear5);
    for (int s = 0; s < 10; ++s) sim.step();
    const std::filesystem::path path = temp_path("mismatched.h5");
    {
        World w = sim.world;
        w.force_of(BodyKind::wire).pop_back();
        ASSERT_TRUE(save_snapshot(w, path).ok());
        const auto r = restore_snapshot(path);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().find("field bodies/wire/force_n has " + std::to_string(w.of(BodyKind::wire).size() - 1)
                                 + " rows, expected " + std::to_string(w.of(BodyKind::wire).size())),
            std::string::npos)
            << r.error();
    }
    {
        World w = sim.world;
        ASSERT_FALSE(w.membrane_forces.node_force_n.empty());
        w.membrane_forces.node_force_n.pop_back();
        ASSERT_TRUE(save_snapshot(w, path).ok());
        const auto r = restore_snapshot(path);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().find("field membrane/node_force_n has"), std::string::npos) << r.error();
    }
    {
        World w = sim.world; // the force stage walks the grid that rows × columns says
        ASSERT_GT(w.membrane.rows, 2u);
        --w.membrane.rows;
        ASSERT_TRUE(save_snapshot(w, path).ok());
        const auto r = restore_snapshot(path);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().find("are not a grid of the"), std::string::npos) << r.error();
    }
    {
        World w = sim.world; // energy and volume read the lists by node
        std::swap(w.membrane.edges[3], w.membrane.edges[4]);
        ASSERT_TRUE(save_snapshot(w, path).ok());
        const auto r = restore_snapshot(path);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().find("field membrane/edges is not the grid's edges"), std::string::npos) << r.error();
    }
    {
        World w = sim.world;
        w.point_loads.set(BodyRef(BodyKind::grain, static_cast<std::uint32_t>(w.of(BodyKind::grain).size())),
            Vec3::UnitZ());
        ASSERT_TRUE(save_snapshot(w, path).ok());
        const auto r = restore_snapshot(path);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().find("point_loads names a body that does not exist"), std::string::npos) << r.error();
    }
    ASSERT_TRUE(save_snapshot(sim.world, path).ok()); // the same column untouched restores
    EXPECT_TRUE(restore_snapshot(path).ok());
    std::filesystem::remove(path);
}

TEST(Snapshot, PointLoadsOutOfBodyOrderAreRefused)
{
    // The gather adds each block's own point loads, which needs the list in
    // body order, each body once (state/point_loads.hpp). A file whose list
    // is not (edited, or written by another program) is refused, saying so;
    // the state hash does not cover the loads (model, not state).
    Simulation sim(1);
    build_wired_column(sim.world, Integrator::gear5);
    World& w = sim.world;
    w.point_loads.set(BodyRef(BodyKind::grain, 2), Vec3(0, 0, -1));
    w.point_loads.set(BodyRef(BodyKind::wire, 1), Vec3(0, 0, -2));
    const std::filesystem::path path = temp_path("point_loads.h5");
    ASSERT_TRUE(save_snapshot(w, path).ok());
    ASSERT_TRUE(restore_snapshot(path).ok()); // as saved
    // The two rows (body, fx, fy, fz) swapped in place.
    const std::array<double, 8> swapped{
        static_cast<double>(w.point_loads[1].first.bits), 0, 0, -2, static_cast<double>(w.point_loads[0].first.bits), 0, 0, -1};
    {
        const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
        ASSERT_GE(file, 0);
        const hid_t d = H5Dopen2(file, "point_loads", H5P_DEFAULT);
        ASSERT_GE(d, 0);
        EXPECT_GE(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, swapped.data()), 0);
        H5Dclose(d);
        H5Fclose(file);
    }
    const auto r = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("field point_loads: entry 1 (grain 2) comes before entry 0 (wire node 1)"), std::string::npos)
        << r.error();
}

TEST(Snapshot, AnUnwritableDirectoryIsAnError)
{
    const auto r = save_snapshot(World{}, "/nonexistent-directory/snapshot.h5");
    ASSERT_FALSE(r.ok());
    // One line: the cause and the file (engine/io/atomic_file.hpp, WriteError).
    EXPECT_EQ(r.error(), "no such file or directory writing /nonexistent-directory/snapshot.h5");
}
