// Why a restored run continues bit-identically.
//
// step() reads nothing but members of World (and the thread pool, whose size
// never changes a result). Every member is written with its exact bits, as
// IEEE doubles or 64-bit integers, and read back into a fresh World; the one
// exception is the cell grid, whose arrays find_pairs overwrites before it
// reads them. So the restored World equals the saved one in every bit a step
// reads, and the steps that follow repeat the same arithmetic on the same
// numbers.
//
// The neighbour list and what follows from it (pair order, per-pair
// prefactors, incidence, wall candidates, positions at the last build) are
// saved, not rebuilt. A rebuild on restore would take place at step N instead
// of at the step of the last build: the list would hold another set of pairs
// (those within the skin at N), the springs would sit at other list positions,
// and the next rebuilds, triggered by the motion since the build, would come
// at other steps. The forces would most likely still agree (pairs apart add
// zeros): forcing a rebuild on restore of tests/engine/wired_column.hpp's
// column gave lists of 312 instead of 320 pairs and other state hashes for
// the next ~300 steps, equal again once both lists were rebuilt at the same
// step. But exactness would then rest on that argument for every stage, now
// and after every change to the pipeline; saving the cache costs some bytes
// per pair and makes exactness hold by construction, at every step. The per-step outputs
// (forces, shares) are saved too, so that a host reading plate forces or
// contact forces right after a restore sees what it would have seen.
#include "io/snapshot.hpp"

#include "forces/membrane_forces.hpp"
#include "io/atomic_file.hpp"
#include "io/hdf5.hpp"
#include "step.hpp"
#include "state/state_hash.hpp"
#include "state/world_fields.hpp"

#include <algorithm>
#include <cinttypes>
#include <map>
#include <cstdio>
#include <span>
#include <system_error>

namespace wiredem::engine {

// A member added to one of these structs must also be listed in
// for_each_field (state/world_fields.hpp), or it is neither saved nor hashed.
// These sizes (x86-64, libstdc++) stop the build until the table is looked at;
// update them together with it.
static_assert(sizeof(World) == 3328, "World changed: update for_each_field and this size");
static_assert(sizeof(Model) == 480, "Model changed: update for_each_field and this size");
static_assert(sizeof(State) == 1536, "State changed: update for_each_field and this size");
// Caches::next_prediction and Caches::near are the members not listed: a
// restored run predicts afresh from the saved derivatives, and selects its
// near pairs afresh, with the same bits. ContactList::rolling_on_ is not
// listed either: it follows from Model::contact.rolling at the next step;
// nor ClumpLoads::member_arm_m, the lever arms one step's first half leaves
// its second.
static_assert(sizeof(Caches) == 1312, "Caches changed: update for_each_field and this size");
static_assert(sizeof(GearPrediction) == 200, "GearPrediction changed: update this size");
static_assert(sizeof(NearPairs) == 192, "NearPairs changed: update this size");
static_assert(sizeof(TranslationalState) == 264, "TranslationalState changed: update for_each_field and this size");
static_assert(sizeof(ClumpState) == 456, "ClumpState changed: update for_each_field and this size");
static_assert(sizeof(ClumpLoads) == 96, "ClumpLoads changed: update for_each_field and this size");
static_assert(sizeof(RotationalState) == 192, "RotationalState changed: update for_each_field and this size");
static_assert(sizeof(Wall) == 112, "Wall changed: update for_each_field and this size");
static_assert(sizeof(WallLoad) == 32, "WallLoad changed: update for_each_field and this size");
static_assert(sizeof(WireChain) == 64, "WireChain changed: update for_each_field and this size");
static_assert(sizeof(WireForces) == 144, "WireForces changed: update for_each_field and this size");
static_assert(sizeof(MembraneMesh) == 200, "MembraneMesh changed: update for_each_field and this size");
static_assert(sizeof(MembraneForces) == 24, "MembraneForces changed: update for_each_field and this size");
static_assert(sizeof(ContactList) == 272, "ContactList changed: update for_each_field and this size");
static_assert(sizeof(ContactSettings) == 64, "ContactSettings changed: update for_each_field and this size");
static_assert(sizeof(TangentialState) == 32, "TangentialState changed: update its FieldCodec and this size");
static_assert(sizeof(ContactOutput) == 64, "ContactOutput changed: update its FieldCodec and this size");
static_assert(sizeof(WireBreak) == 32, "WireBreak changed: update its FieldCodec and this size");

namespace {

constexpr const char* format_name = "wiredem snapshot";

std::string hex(std::uint64_t h)
{
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016" PRIx64, h);
    return buf;
}

} // namespace

Result<std::uint64_t, std::string> save_snapshot(const World& w, const std::filesystem::path& path)
{
    return save_snapshot(w, path, {});
}

Result<std::uint64_t, std::string> save_snapshot(
    const World& w, const std::filesystem::path& path, const std::function<void(io::Group&)>& write_host)
{
    const std::uint64_t hash = state_hash(w);
    try {
        io::write_file_atomically(path, [&](io::Group& root) {
            root.write_string_attribute("format", format_name);
            root.write_int_attribute("version", snapshot_version);
            root.write_int_attribute("wall_count", static_cast<std::int64_t>(w.walls.size()));
            root.write_string_attribute("state_hash", hex(hash));
            for_each_field(w, [&](const std::string& name, const auto& value, FieldRole) {
                const FlatField f = flatten(value);
                if (f.is_real) root.write_dataset(name, std::span<const double>(f.real), f.columns);
                else root.write_dataset(name, std::span<const std::int64_t>(f.integer), f.columns);
            });
            if (write_host) {
                io::Group host = root.create_group(snapshot_host_group);
                write_host(host);
            }
        });
    } catch (const std::exception& e) {
        return Err(io::write_failure_text("cannot write snapshot " + path.string() + ": ", e));
    }
    return hash;
}

namespace {

/// Whether the membrane's nodes form its grid ("" when they do, or there are none).
std::string membrane_grid_error(const World& w)
{
    const MembraneMesh& m = w.membrane;
    const std::size_t nodes = w.of(BodyKind::membrane).size();
    if (nodes == 0) return "";
    if (m.rows < 2 || m.columns < 3 || m.rows > nodes || nodes / m.rows != m.columns || nodes % m.rows != 0)
        return "fields membrane/rows and membrane/columns (" + std::to_string(m.rows) + " × " + std::to_string(m.columns)
               + ") are not a grid of the " + std::to_string(nodes) + " membrane nodes (at least 2 rows of 3)";
    return "";
}

/// Versions 2 to 5 list the membrane's edges by (lower, higher) node and its
/// triangles quad by quad: puts them in grid order (state/membrane.hpp), each
/// edge with its rest length ("" when done).
std::string membrane_into_grid_order(World& w)
{
    MembraneMesh& m = w.membrane;
    if (w.of(BodyKind::membrane).size() == 0) return "";
    if (std::string error = membrane_grid_error(w); !error.empty()) return error;
    if (m.edge_rest_m.size() != m.edges.size()) return "fields membrane/edges and membrane/edge_rest_m differ in length";
    std::map<std::pair<std::uint32_t, std::uint32_t>, double> rest;
    for (std::size_t e = 0; e < m.edges.size(); ++e)
        rest[std::minmax(m.edges[e][0], m.edges[e][1])] = m.edge_rest_m[e];
    std::vector<std::array<std::uint32_t, 2>> edges = membrane_grid_edges(m.rows, m.columns);
    if (edges.size() != rest.size())
        return "field membrane/edges has " + std::to_string(rest.size()) + " edges, the membrane's grid "
               + std::to_string(edges.size());
    std::vector<double> rests;
    rests.reserve(edges.size());
    for (const auto& e : edges) {
        const auto found = rest.find(std::minmax(e[0], e[1]));
        if (found == rest.end())
            return "field membrane/edges lacks the grid's edge (" + std::to_string(e[0]) + ", " + std::to_string(e[1]) + ")";
        rests.push_back(found->second);
    }
    m.edges = std::move(edges);
    m.edge_rest_m = std::move(rests);
    m.triangles = membrane_grid_triangles(m.rows, m.columns);
    return "";
}

/// What does not fit together in a restored World: the arrays a step
/// indexes by body, grain, wire node or membrane element must have as many
/// entries as there are of those ("" when all do). save_snapshot always writes them so;
/// a file that was edited would otherwise be stepped out of bounds.
std::string mismatched_sizes(const World& w)
{
    const auto check = [](std::string& error, std::size_t size, std::size_t expected, const std::string& name) {
        if (error.empty() && size != expected)
            error = "field " + name + " has " + std::to_string(size) + " rows, expected " + std::to_string(expected);
    };
    std::string error;
    for (int k = 0; k < body_kind_count; ++k) {
        const TranslationalState& b = w.bodies[k];
        const std::string at = std::string("bodies/") + field_kind_names[k] + "/";
        const std::size_t n = b.radius_m.size();
        for (int d = 0; d < gear_order; ++d) check(error, b.x[d].size(), n, at + "x" + std::to_string(d));
        check(error, b.mass_kg.size(), n, at + "mass_kg");
        check(error, b.inv_mass_per_kg.size(), n, at + "inv_mass_per_kg");
        check(error, b.motion.size(), n, at + "motion");
        check(error, b.material.size(), n, at + "material");
        check(error, w.body_force_n[k].size(), n, at + "force_n");
    }
    const std::size_t grains = w.of(BodyKind::grain).size();
    const RotationalState& rot = w.grain_rotation;
    for (int d = 0; d < gear_order; ++d) check(error, rot.theta[d].size(), grains, "grain_rotation/w" + std::to_string(d));
    check(error, rot.orientation.size(), grains, "grain_rotation/orientation");
    check(error, rot.inv_inertia_per_kg_m2.size(), grains, "grain_rotation/inv_inertia_per_kg_m2");
    check(error, w.grain_torque_n_m.size(), grains, "grain_rotation/torque_n_m");
    const std::size_t nodes = w.of(BodyKind::wire).size();
    check(error, w.wire_rest_angle_rad.size(), nodes, "wire/rest_angle_rad");
    check(error, w.wire_forces.node_force_n.size(), nodes, "wire/node_force_n");
    check(error, w.wire_forces.bending_force_n[0].size(), nodes, "wire/bending_force_on_previous_n");
    check(error, w.wire_forces.bending_force_n[1].size(), nodes, "wire/bending_force_on_node_n");
    check(error, w.wire_forces.bending_force_n[2].size(), nodes, "wire/bending_force_on_next_n");
    check(error, w.wire_forces.segment_force_n.size(), nodes > 0 ? nodes - 1 : 0, "wire/segment_force_n");
    check(error, w.wire_forces.segment_strain.size(), nodes > 0 ? nodes - 1 : 0, "wire/segment_strain");
    for (const WireBreak& b : w.wire_breaks)
        if (error.empty() && (b.segment + std::size_t{1} >= nodes || static_cast<std::uint8_t>(b.cause) > 1))
            error = "field wire/breaks names a segment the wire does not have, or an unknown cause";
    const MembraneMesh& m = w.membrane;
    if (error.empty()) error = membrane_grid_error(w);
    const std::size_t membrane_nodes = w.of(BodyKind::membrane).size();
    // The force stage walks the grid; energy and volume read the lists.
    if (error.empty() && membrane_nodes > 0 && m.edges != membrane_grid_edges(m.rows, m.columns))
        error = "field membrane/edges is not the grid's edges in grid order";
    if (error.empty() && membrane_nodes > 0 && m.triangles != membrane_grid_triangles(m.rows, m.columns))
        error = "field membrane/triangles is not the grid's triangles in grid order";
    if (error.empty() && membrane_nodes == 0 && !(m.edges.empty() && m.triangles.empty()))
        error = "fields membrane/edges and membrane/triangles list elements of a membrane without nodes";
    check(error, m.edge_rest_m.size(), m.edges.size(), "membrane/edge_rest_m");
    check(error, m.node_fixed.size(), membrane_nodes, "membrane/node_fixed");
    check(error, m.node_mass_kg.size(), membrane_nodes, "membrane/node_mass_kg");
    check(error, w.membrane_forces.node_force_n.size(), membrane_nodes, "membrane/node_force_n");
    if (!w.contacts.rolling_rad.empty()) {
        check(error, w.contacts.rolling_rad.size(), w.contacts.size(), "contacts/rolling_rad");
        check(error, w.contacts.rolling_torque_n_m.size(), w.contacts.size(), "contacts/rolling_torque_n_m");
    }
    const ClumpState& cl = w.clumps;
    if (!cl.empty()) {
        const std::size_t n = cl.size();
        for (int d = 0; d < gear_order; ++d) {
            check(error, cl.x[d].size(), n, "clumps/x" + std::to_string(d));
            check(error, cl.omega[d].size(), n, "clumps/omega" + std::to_string(d));
        }
        check(error, cl.orientation.size(), n, "clumps/orientation");
        check(error, cl.principal_inertia_kg_m2.size(), n, "clumps/principal_inertia_kg_m2");
        check(error, cl.first_member.size(), n, "clumps/first_member");
        check(error, cl.member_count.size(), n, "clumps/member_count");
        check(error, w.clump_loads.force_n.size(), n, "clumps/force_n");
        check(error, w.clump_loads.torque_n_m.size(), n, "clumps/torque_n_m");
        check(error, w.clump_loads.predicted_orientation.size(), n, "clumps/predicted_orientation");
        check(error, cl.member_clump.size(), grains, "clumps/member_clump");
        check(error, cl.member_offset_m.size(), grains, "clumps/member_offset_m");
        for (std::size_t i = 0; error.empty() && i < n; ++i)
            if (cl.first_member[i] + std::uint64_t{cl.member_count[i]} > grains)
                error = "field clumps/first_member names spheres that are not grains";
    }
    for (const auto& [body, f] : w.point_loads)
        if (error.empty() && (is_wall(body) || body.index() >= w.of(body.kind()).size()))
            error = "field point_loads names a body that does not exist";
    return error;
}

/// A version-2 snapshot held a body by an inverse mass of 0 (the triaxial
/// test's cap nodes too, which its driver moved by hand; run_triaxial makes
/// them kinematic again when it continues): those bodies become fixed, with
/// the inverse of their mass.
void motion_from_held_bodies(World& w)
{
    for (TranslationalState& body : w.bodies) {
        body.motion.assign(body.size(), Motion::dynamic);
        for (std::size_t i = 0; i < body.size(); ++i) {
            if (body.inv_mass_per_kg[i] != 0.0) continue;
            body.motion[i] = Motion::fixed;
            if (body.mass_kg[i] > 0.0) body.inv_mass_per_kg[i] = 1.0 / body.mass_kg[i];
        }
    }
}

/// Versions 2 and 3 kept a contact's outputs in four arrays (force_n,
/// normal_x_tangential_n, overlap_m, normal_force_n): read them into the
/// records. Returns an error message, or "".
std::string read_four_output_arrays(const io::Group& root, ContactList& c)
{
    std::vector<Vec3> force, torque_arm;
    std::vector<double> overlap, normal;
    std::string error;
    auto read = [&](const std::string& name, auto& value) {
        if (!error.empty()) return;
        if (!root.exists(name)) {
            error = "field " + name + " is missing";
            return;
        }
        const io::Dataset d = root.open_dataset(name);
        const std::vector<std::size_t> shape = d.shape();
        if (shape.size() != 2 || !unflatten(d.read_doubles(), shape[0], value) || value.size() != c.size())
            error = "field " + name + " has an unexpected shape";
    };
    read("contacts/force_n", force);
    read("contacts/normal_x_tangential_n", torque_arm);
    read("contacts/overlap_m", overlap);
    read("contacts/normal_force_n", normal);
    if (!error.empty()) return error;
    c.output.resize(c.size());
    for (std::size_t p = 0; p < c.size(); ++p) c.output[p] = {.force_n = force[p], .overlap_m = overlap[p], .normal_x_tangential_n = torque_arm[p], .normal_force_n = normal[p]};
    return "";
}

} // namespace

Result<World, std::string> restore_snapshot(const std::filesystem::path& path)
{
    return restore_snapshot(path, {});
}

Result<World, std::string> restore_snapshot(
    const std::filesystem::path& path, const std::function<void(const io::Group&)>& read_host)
{
    const std::string at = "snapshot " + path.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return Err(at + ": no such file");
    World w;
    try {
        const io::File file = io::File::open_read_only(path);
        const io::Group root = file.root();
        if (!root.has_attribute("format") || root.read_string_attribute("format") != format_name)
            return Err(at + ": not a wiredem snapshot (no format attribute \"" + std::string(format_name) + "\")");
        const std::int64_t version = root.read_int_attribute("version");
        if (version < 2 || version > snapshot_version)
            return Err(at + ": version " + std::to_string(version) + ", but this engine reads versions 2 to "
                       + std::to_string(snapshot_version));
        // Version 2 has no motion types: it held a body by its inverse mass.
        const bool motion_from_inverse_mass = version == 2;
        // Versions 2 and 3 keep a contact's outputs in four arrays.
        const bool outputs_in_four_arrays = version <= 3;
        // Versions 2 to 4 sort the body pairs by (first, second) alone.
        const bool pairs_by_bodies = version <= 4;
        // Versions 2 to 5 list the membrane's elements in another order, and
        // keep a wire joint's three bending forces in one record (an output:
        // the next step writes them before anything reads them).
        const bool membrane_by_nodes = version <= 5;
        const bool bending_in_records = version <= 5;
        // Versions 2 to 5 work the skin out every step: the list's is today's.
        const bool skin_not_kept = version <= 5;
        // Versions 2 to 6 have no rolling resistance: the law is off.
        const bool rolling_not_kept = version <= 6;
        // Versions 2 to 7 have no wall friction of their own: the contact law's.
        const bool wall_friction_not_kept = version <= 7;
        const auto walls = static_cast<std::size_t>(root.read_int_attribute("wall_count"));
        w.walls.resize(walls);
        w.wall_point_at_build_m.resize(walls);
        w.wall_loads.resize(walls);
        // Versions 2 to 8 have no breakable wire: it is unbreakable and whole.
        const bool wire_unbreakable = version <= 8;
        // Removed wire segments saved: make them present, so that
        // for_each_field lists them and they are read.
        if (root.exists("wire/breaks")) w.wire_breaks.resize(1);
        // Rolling springs saved: make them present, so that for_each_field
        // lists them (it lists them only when there are any) and they are read.
        if (root.exists("contacts/rolling_rad")) w.contacts.rolling_rad.resize(1);
        // Clumps saved (version 10 on): likewise.
        if (root.exists("clumps/mass_kg")) w.clumps.mass_kg.resize(1);
        std::string error;
        for_each_field(w, [&](const std::string& name, auto& value, FieldRole) {
            if (!error.empty()) return;
            if (motion_from_inverse_mass && name.ends_with("/motion")) return; // below
            if (outputs_in_four_arrays && name == "contacts/output") return;  // below
            if (bending_in_records && name.starts_with("wire/bending_force_on_")) return; // below
            if (skin_not_kept && name == "skin_at_build_m") return;                       // below
            if (rolling_not_kept && name.starts_with("contact/rolling_")) return;         // off
            if (wall_friction_not_kept && name.starts_with("walls/") && name.ends_with("/friction_coeff")) return;
            if (wire_unbreakable && name == "wire/breaking_strain") return;               // +∞
            if (!root.exists(name)) {
                error = "field " + name + " is missing";
                return;
            }
            const io::Dataset d = root.open_dataset(name);
            const std::vector<std::size_t> shape = d.shape();
            using Value = std::remove_cvref_t<decltype(value)>;
            using Number = typename FieldCodec<FieldElement<Value>>::Number;
            if constexpr (std::is_same_v<Value, PointLoads>) {
                // The loads' order is the type's invariant, which the gather
                // relies on: a file that breaks it is refused, saying how.
                std::vector<PointLoads::Load> list;
                if (shape.size() != 2 || !unflatten(d.read_doubles(), shape[0], list)) {
                    error = "field " + name + " has an unexpected shape";
                    return;
                }
                auto loads = PointLoads::from_sorted(std::move(list));
                if (loads) value = std::move(loads).value();
                else error = "field " + name + ": " + loads.error();
                return;
            }
            bool read = false;
            if (shape.size() == 2) {
                if constexpr (std::is_same_v<Number, double>) read = unflatten(d.read_doubles(), shape[0], value);
                else read = unflatten(d.read_int64s(), shape[0], value);
            }
            if (!read) error = "field " + name + " has an unexpected shape";
        });
        if (!error.empty()) return Err(at + ": " + error);
        if (bending_in_records)
            for (std::vector<Vec3>& on : w.wire_forces.bending_force_n) on.assign(w.of(BodyKind::wire).size(), Vec3::Zero());
        if (skin_not_kept) w.skin_at_build_m = effective_skin_m(w);
        if (membrane_by_nodes) error = membrane_into_grid_order(w);
        if (!error.empty()) return Err(at + ": " + error);
        error = mismatched_sizes(w);
        if (!error.empty()) return Err(at + ": " + error);
        if (motion_from_inverse_mass) motion_from_held_bodies(w);
        if (outputs_in_four_arrays) {
            error = read_four_output_arrays(root, w.contacts);
            if (!error.empty()) return Err(at + ": " + error);
        }
        const std::string recorded = root.read_string_attribute("state_hash");
        if (hex(state_hash(w)) != recorded)
            return Err(at + ": the restored state hashes to " + hex(state_hash(w)) + ", the file recorded " + recorded);
        if (pairs_by_bodies) w.contacts.sort(w.walls.size(), w.flat_offsets());
        if (read_host) {
            if (!root.exists(snapshot_host_group)) return Err(at + ": it has no /host group (saved without the host's state)");
            read_host(root.open_group(snapshot_host_group));
        }
    } catch (const std::exception& e) {
        return Err(at + ": " + e.what());
    }
    return w;
}

} // namespace wiredem::engine
