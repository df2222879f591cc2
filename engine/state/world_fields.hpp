// Every member of a World, listed once: the snapshot writes and reads these
// fields, state_hash hashes the ones whose role is `state`. A new World member
// is one line in for_each_field (the static_asserts in io/snapshot.cpp fail
// until it is there); a member of a new type also needs a FieldCodec.
//
// Each field is flattened to a table of numbers, rows × columns, either
// doubles (real quantities; also small integers and flags inside a mixed
// record, which doubles hold exactly) or 64-bit integers (ids, counts,
// flags, enums): a scalar is one row, a vector one row per element.
#pragma once

#include "state/world.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace wiredem::engine {

/// What a field is to a step.
enum class FieldRole : std::uint8_t {
    model,   ///< the definition: materials, radii, masses, topology, parameters, loads
    state,   ///< what the step advances: state_hash covers exactly these
    cache,   ///< derived from model and state: the neighbour list and what it decides
    output,  ///< written by every step before it is read (forces, per-step slots)
};

/// How a value of type T becomes `columns` numbers of type Number (double or
/// std::int64_t) per row. Specialised below for every element type a World holds.
template <class T, class Enable = void>
struct FieldCodec;

/// Integers, flags and enums: one integer column.
template <class T>
struct FieldCodec<T, std::enable_if_t<std::is_integral_v<T> || std::is_enum_v<T>>> {
    using Number = std::int64_t;
    static constexpr std::size_t columns = 1;
    static void put(const T& v, Number* out) { out[0] = static_cast<Number>(v); }
    static void get(const Number* in, T& v) { v = static_cast<T>(in[0]); }
};

template <>
struct FieldCodec<double> {
    using Number = double;
    static constexpr std::size_t columns = 1;
    static void put(double v, Number* out) { out[0] = v; }
    static void get(const Number* in, double& v) { v = in[0]; }
};

template <>
struct FieldCodec<Vec3> {
    using Number = double;
    static constexpr std::size_t columns = 3;
    static void put(const Vec3& v, Number* out) { out[0] = v.x(), out[1] = v.y(), out[2] = v.z(); }
    static void get(const Number* in, Vec3& v) { v = Vec3(in[0], in[1], in[2]); }
};

template <>
struct FieldCodec<Quat> {
    using Number = double;
    static constexpr std::size_t columns = 4;
    static void put(const Quat& q, Number* out) { out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z(); }
    static void get(const Number* in, Quat& q) { q = Quat(in[0], in[1], in[2], in[3]); }
};

template <>
struct FieldCodec<BodyRef> {
    using Number = std::int64_t;
    static constexpr std::size_t columns = 1;
    static void put(const BodyRef& b, Number* out) { out[0] = b.bits; }
    static void get(const Number* in, BodyRef& b) { b.bits = static_cast<std::uint32_t>(in[0]); }
};

/// Spring (x, y, z) and sticking (1/0).
template <>
struct FieldCodec<TangentialState> {
    using Number = double;
    static constexpr std::size_t columns = 4;
    static void put(const TangentialState& s, Number* out)
    {
        FieldCodec<Vec3>::put(s.spring_m, out);
        out[3] = s.sticking ? 1.0 : 0.0;
    }
    static void get(const Number* in, TangentialState& s)
    {
        FieldCodec<Vec3>::get(in, s.spring_m);
        s.sticking = in[3] != 0.0;
    }
};

/// An optional real: present (1/0), value (0 when absent).
template <>
struct FieldCodec<std::optional<double>> {
    using Number = double;
    static constexpr std::size_t columns = 2;
    static void put(const std::optional<double>& v, Number* out)
    {
        out[0] = v ? 1.0 : 0.0;
        out[1] = v.value_or(0.0);
    }
    static void get(const Number* in, std::optional<double>& v)
    {
        v = in[0] != 0.0 ? std::optional<double>(in[1]) : std::nullopt;
    }
};

/// Force (x, y, z), n × F_t (x, y, z), overlap, |F_n|.
template <>
struct FieldCodec<ContactOutput> {
    using Number = double;
    static constexpr std::size_t columns = 8;
    static void put(const ContactOutput& o, Number* out)
    {
        FieldCodec<Vec3>::put(o.force_n, out);
        FieldCodec<Vec3>::put(o.normal_x_tangential_n, out + 3);
        out[6] = o.overlap_m;
        out[7] = o.normal_force_n;
    }
    static void get(const Number* in, ContactOutput& o)
    {
        FieldCodec<Vec3>::get(in, o.force_n);
        FieldCodec<Vec3>::get(in + 3, o.normal_x_tangential_n);
        o.overlap_m = in[6];
        o.normal_force_n = in[7];
    }
};

/// Segment and cause (exact in a double), time, strain, released energy.
template <>
struct FieldCodec<WireBreak> {
    using Number = double;
    static constexpr std::size_t columns = 5;
    static void put(const WireBreak& b, Number* out)
    {
        out[0] = b.segment, out[1] = static_cast<double>(b.cause), out[2] = b.time_s, out[3] = b.strain;
        out[4] = b.released_energy_j;
    }
    static void get(const Number* in, WireBreak& b)
    {
        b.segment = static_cast<std::uint32_t>(in[0]);
        b.cause = static_cast<WireBreakCause>(static_cast<std::uint8_t>(in[1]));
        b.time_s = in[2], b.strain = in[3], b.released_energy_j = in[4];
    }
};

/// E, ν, ρ.
template <>
struct FieldCodec<Material> {
    using Number = double;
    static constexpr std::size_t columns = 3;
    static void put(const Material& m, Number* out)
    {
        out[0] = m.youngs_modulus_pa, out[1] = m.poisson_ratio, out[2] = m.density_kg_per_m3;
    }
    static void get(const Number* in, Material& m) { m = Material{in[0], in[1], in[2]}; }
};

/// Contact index · 2 + side (Incidence::bits).
template <>
struct FieldCodec<Incidence> {
    using Number = std::int64_t;
    static constexpr std::size_t columns = 1;
    static void put(const Incidence& e, Number* out) { out[0] = e.bits; }
    static void get(const Number* in, Incidence& e) { e.bits = static_cast<std::uint32_t>(in[0]); }
};

/// Body (its BodyRef bits, exact in a double) and force (x, y, z).
template <>
struct FieldCodec<std::pair<BodyRef, Vec3>> {
    using Number = double;
    static constexpr std::size_t columns = 4;
    static void put(const std::pair<BodyRef, Vec3>& p, Number* out)
    {
        out[0] = p.first.bits;
        FieldCodec<Vec3>::put(p.second, out + 1);
    }
    static void get(const Number* in, std::pair<BodyRef, Vec3>& p)
    {
        p.first.bits = static_cast<std::uint32_t>(in[0]);
        FieldCodec<Vec3>::get(in + 1, p.second);
    }
};

/// A fixed-size array of elements: their columns side by side (edge and
/// triangle node ids, the bending forces on three nodes, the kind flags).
template <class E, std::size_t N>
struct FieldCodec<std::array<E, N>> {
    using Number = typename FieldCodec<E>::Number;
    static constexpr std::size_t columns = N * FieldCodec<E>::columns;
    static void put(const std::array<E, N>& a, Number* out)
    {
        for (std::size_t i = 0; i < N; ++i) FieldCodec<E>::put(a[i], out + i * FieldCodec<E>::columns);
    }
    static void get(const Number* in, std::array<E, N>& a)
    {
        for (std::size_t i = 0; i < N; ++i) FieldCodec<E>::get(in + i * FieldCodec<E>::columns, a[i]);
    }
};

/// A field flattened: rows × columns numbers of one type.
struct FlatField {
    std::vector<double> real;           ///< used when the codec's Number is double
    std::vector<std::int64_t> integer;  ///< used when it is std::int64_t
    std::size_t columns = 1;
    bool is_real = true;
};

namespace detail {
template <class T>
struct IsVector : std::false_type {};
template <class E, class A>
struct IsVector<std::vector<E, A>> : std::true_type {};

template <class T>
struct ElementOf {
    using type = T;
};
template <class E, class A>
struct ElementOf<std::vector<E, A>> {
    using type = E;
};
/// The material table is saved as its list of materials (flatten and
/// unflatten below); the pair table follows from it.
template <>
struct ElementOf<MaterialTable> {
    using type = Material;
};
/// The point loads likewise, as their list.
template <>
struct ElementOf<PointLoads> {
    using type = PointLoads::Load;
};
} // namespace detail

/// The element type of a field: E for std::vector<E>, T for a scalar.
template <class T>
using FieldElement = typename detail::ElementOf<T>::type;

/// Flattens a scalar (one row) or a vector (one row per element).
template <class T>
FlatField flatten(const T& value)
{
    using E = FieldElement<T>;
    using C = FieldCodec<E>;
    FlatField f;
    f.columns = C::columns;
    f.is_real = std::is_same_v<typename C::Number, double>;
    auto& out = [&]() -> std::vector<typename C::Number>& {
        if constexpr (std::is_same_v<typename C::Number, double>) return f.real;
        else return f.integer;
    }();
    if constexpr (detail::IsVector<T>::value) {
        out.resize(value.size() * C::columns);
        for (std::size_t i = 0; i < value.size(); ++i) C::put(value[i], out.data() + i * C::columns);
    } else {
        out.resize(C::columns);
        C::put(value, out.data());
    }
    return f;
}

/// Restores a value from `rows` rows of numbers (C::columns each): a vector
/// takes any number of rows, a scalar exactly one (false otherwise).
template <class T, class Number>
bool unflatten(const std::vector<Number>& numbers, std::size_t rows, T& value)
{
    using C = FieldCodec<FieldElement<T>>;
    static_assert(std::is_same_v<typename C::Number, Number>);
    if (numbers.size() != rows * C::columns) return false;
    if constexpr (detail::IsVector<T>::value) {
        value.resize(rows);
        for (std::size_t i = 0; i < rows; ++i) C::get(numbers.data() + i * C::columns, value[i]);
        return true;
    } else {
        if (rows != 1) return false;
        C::get(numbers.data(), value);
        return true;
    }
}

/// The material table as a vector of materials, one row each.
inline FlatField flatten(const MaterialTable& table)
{
    return flatten(std::vector<Material>(table.begin(), table.end()));
}

/// Refills a material table (and so its pair table) from its rows.
template <class Number>
bool unflatten(const std::vector<Number>& numbers, std::size_t rows, MaterialTable& table)
{
    std::vector<Material> list;
    if (!unflatten(numbers, rows, list)) return false;
    table = MaterialTable{};
    for (const Material& m : list) table.add(m);
    return true;
}

/// The point loads as their list, one row per load.
inline FlatField flatten(const PointLoads& loads) { return flatten(loads.list()); }

/// Refills the point loads from their rows; false when the rows are not in
/// the list's order (PointLoads::from_sorted, whose message the snapshot
/// reader gives).
template <class Number>
bool unflatten(const std::vector<Number>& numbers, std::size_t rows, PointLoads& loads)
{
    std::vector<PointLoads::Load> list;
    if (!unflatten(numbers, rows, list)) return false;
    auto sorted = PointLoads::from_sorted(std::move(list));
    if (!sorted) return false;
    loads = std::move(sorted).value();
    return true;
}

/// Names of the body kinds in field names, by BodyKind.
inline constexpr std::array<const char*, body_kind_count> field_kind_names{"grain", "wire", "membrane"};

/// Calls field(name, member, role) for every member of `w` (W = World or
/// const World), in a fixed order (state_hash hashes in it). Walls are
/// visited as "walls/<i>/…" for i < w.walls.size(): a reader sizes w.walls,
/// w.wall_point_at_build_m and w.wall_loads first (resize_walls). The role
/// follows the part of the World a member is in (Model: model; State: state;
/// Caches: cache, or output for what a step writes before it reads it), with
/// one exception: the contacts' memory (tangential springs, touching flags,
/// rolling springs while the rolling law is on) is state kept in the
/// neighbour list, which carries it across rebuilds.
///
/// Not listed: Caches::grid, whose arrays are scratch that find_pairs rebuilds
/// from the positions before it reads them.
template <class W, class Visit>
void for_each_field(W& w, Visit&& field)
{
    using R = FieldRole;
    // Clock and integrator.
    field("integrator", w.integrator, R::model);
    field("dt_s", w.dt_s, R::state); // the scaled derivatives are scaled by it
    field("time_s", w.time_s, R::state);
    field("step_count", w.step_count, R::state);

    // What every contact and body shares.
    field("materials", w.materials, R::model);
    field("contact/normal_damping_s", w.contact.normal_damping_s, R::model);
    field("contact/tangential_stiffness_per_m", w.contact.tangential.stiffness_per_m, R::model);
    field("contact/friction_coeff", w.contact.tangential.friction_coeff, R::model);
    field("contact/critical_slip_m", w.contact.tangential.critical_slip_m, R::model);
    field("contact/tangential_damping_s_per_m", w.contact.tangential.damping_s_per_m, R::model);
    field("contact/rolling_friction_coeff", w.contact.rolling.friction_coeff, R::model);
    field("contact/rolling_stiffness_factor", w.contact.rolling.stiffness_factor, R::model);
    field("contact/rolling_damping_ratio", w.contact.rolling.damping_ratio, R::model);
    field("wire_contact_skip", w.wire_contact_skip, R::model);
    field("gravity_m_per_s2", w.gravity_m_per_s2, R::model);
    field("gravity_acts", w.gravity_acts, R::model);
    field("kinds_interact", w.kinds_interact, R::model);
    field("point_loads", w.point_loads, R::model);
    field("skin_m", w.skin_m, R::model);

    // Bodies, by kind.
    for (int k = 0; k < body_kind_count; ++k) {
        auto& b = w.bodies[k];
        const std::string at = std::string("bodies/") + field_kind_names[k] + "/";
        for (int d = 0; d < gear_order; ++d) field(at + "x" + std::to_string(d), b.x[d], R::state);
        field(at + "radius_m", b.radius_m, R::model);
        field(at + "mass_kg", b.mass_kg, R::model);
        field(at + "inv_mass_per_kg", b.inv_mass_per_kg, R::model);
        field(at + "motion", b.motion, R::model);
        field(at + "material", b.material, R::model);
        field(at + "force_n", w.body_force_n[k], R::output);
    }
    auto& rot = w.grain_rotation;
    // The datasets keep the name the member had until 2026-12-02 (w), so that older snapshots restore.
    // (A std::string on the left of +: GCC 12 warns -Warray-bounds, wrongly,
    // on a literal + std::string&& inlined here.)
    const std::string rotation_at = "grain_rotation/w";
    for (int d = 0; d < gear_order; ++d) field(rotation_at + std::to_string(d), rot.theta[d], R::state);
    field("grain_rotation/orientation", rot.orientation, R::state);
    field("grain_rotation/inv_inertia_per_kg_m2", rot.inv_inertia_per_kg_m2, R::model);
    field("grain_rotation/torque_n_m", w.grain_torque_n_m, R::output);

    // Clumps (state/clump_state.hpp): listed only when there are any, so that
    // without them neither the hash nor a snapshot changes (a restore marks
    // them present first when the file has them: io/snapshot.cpp).
    if (!w.clumps.empty()) {
        auto& cl = w.clumps;
        for (int d = 0; d < gear_order; ++d) field("clumps/x" + std::to_string(d), cl.x[d], R::state);
        for (int d = 0; d < gear_order; ++d) field("clumps/omega" + std::to_string(d), cl.omega[d], R::state);
        field("clumps/orientation", cl.orientation, R::state);
        field("clumps/mass_kg", cl.mass_kg, R::model);
        field("clumps/principal_inertia_kg_m2", cl.principal_inertia_kg_m2, R::model);
        field("clumps/first_member", cl.first_member, R::model);
        field("clumps/member_count", cl.member_count, R::model);
        field("clumps/member_clump", cl.member_clump, R::model);
        field("clumps/member_offset_m", cl.member_offset_m, R::model);
        field("clumps/force_n", w.clump_loads.force_n, R::output);
        field("clumps/torque_n_m", w.clump_loads.torque_n_m, R::output);
        field("clumps/predicted_orientation", w.clump_loads.predicted_orientation, R::output);
    }

    // Walls. Their contacts (springs and touching flags) are in the contact
    // list, below; where a wall was at the last rebuild is cache.
    for (std::size_t i = 0; i < w.walls.size(); ++i) {
        auto& wall = w.walls[i];
        const std::string at = "walls/" + std::to_string(i) + "/";
        field(at + "shape", wall.shape, R::model);
        field(at + "normal", wall.normal, R::model);
        field(at + "radius_m", wall.radius_m, R::model);
        field(at + "material", wall.material, R::model);
        field(at + "friction_coeff", wall.friction_coeff, R::model);
        field(at + "point_m", wall.point_m, R::state);
        field(at + "velocity_m_per_s", wall.velocity_m_per_s, R::state);
        field(at + "point_at_build_m", w.wall_point_at_build_m[i], R::cache);
        field(at + "total_force_n", w.wall_loads[i].total_force_n, R::output);
        field(at + "contacts", w.wall_loads[i].contacts, R::output);
    }

    // The wire: parameters, the plastic joints' rest angles, per-step slots.
    auto& wire = w.wire;
    field("wire/radius_m", wire.radius_m, R::model);
    field("wire/segment_length_m", wire.segment_length_m, R::model);
    field("wire/axial_stiffness_n_per_m", wire.axial_stiffness_n_per_m, R::model);
    field("wire/bending_stiffness_n_m", wire.bending_stiffness_n_m, R::model);
    field("wire/bending_yield_angle_rad", wire.bending_yield_angle_rad, R::model);
    field("wire/node_mass_kg", wire.node_mass_kg, R::model);
    field("wire/material", wire.material, R::model);
    field("wire/breaking_strain", wire.breaking_strain, R::model);
    field("wire/rest_angle_rad", w.wire_rest_angle_rad, R::state);
    // The removed segments: listed only when there are any, so that a whole
    // wire's hash and snapshot do not change (a restore marks them present
    // first when the file has them: io/snapshot.cpp).
    if (!w.wire_breaks.empty()) field("wire/breaks", w.wire_breaks, R::state);
    field("wire/segment_force_n", w.wire_forces.segment_force_n, R::output);
    field("wire/bending_force_on_previous_n", w.wire_forces.bending_force_n[0], R::output);
    field("wire/bending_force_on_node_n", w.wire_forces.bending_force_n[1], R::output);
    field("wire/bending_force_on_next_n", w.wire_forces.bending_force_n[2], R::output);
    field("wire/node_force_n", w.wire_forces.node_force_n, R::output);
    field("wire/segment_strain", w.wire_forces.segment_strain, R::output);

    // The membrane: parameters, mesh, incidence, per-step slots.
    auto& m = w.membrane;
    field("membrane/radius_m", m.radius_m, R::model);
    field("membrane/height_m", m.height_m, R::model);
    field("membrane/base_z_m", m.base_z_m, R::model);
    field("membrane/edge_stiffness_n_per_m", m.edge_stiffness_n_per_m, R::model);
    field("membrane/edge_law", m.edge_law, R::model);
    field("membrane/node_area_m2", m.node_area_m2, R::model);
    field("membrane/pressure_pa", m.pressure_pa, R::model);
    field("membrane/rigid", m.rigid, R::model);
    field("membrane/columns", m.columns, R::model);
    field("membrane/rows", m.rows, R::model);
    field("membrane/edges", m.edges, R::model);
    field("membrane/edge_rest_m", m.edge_rest_m, R::model);
    field("membrane/triangles", m.triangles, R::model);
    field("membrane/node_fixed", m.node_fixed, R::model);
    field("membrane/node_mass_kg", m.node_mass_kg, R::model);
    field("membrane/node_force_n", w.membrane_forces.node_force_n, R::output);

    // Contacts, body pairs and body–wall: the springs and touching flags are
    // state; the list itself (which contacts, in which order, and what
    // follows from that) is cache, kept so that a restored run rebuilds it at
    // the same steps. The per-step slots of a contact apart are zero, which
    // the kernel relies on: they are saved too.
    auto& c = w.contacts;
    field("contacts/tangential", c.tangential, R::state);
    field("contacts/touching", c.touching, R::state);
    // The rolling springs exist only while the rolling law is on and the
    // list has contacts (ContactList::keep_rolling): listed only then, so
    // that without them neither the hash nor a snapshot changes (a restore
    // marks them present first when the file has them: io/snapshot.cpp).
    if (!c.rolling_rad.empty()) {
        field("contacts/rolling_rad", c.rolling_rad, R::state);
        field("contacts/rolling_torque_n_m", c.rolling_torque_n_m, R::output);
    }
    field("contacts/first", c.first, R::cache);
    field("contacts/second", c.second, R::cache);
    field("contacts/wall_start", c.wall_start, R::cache);
    field("contacts/hertz_coefficient", c.hertz_coefficient, R::cache);
    field("contacts/incidence_start", c.incidence_start, R::cache);
    field("contacts/incidence", c.incidence, R::cache);
    field("contacts/output", c.output, R::output);
    field("position_at_build_m", w.position_at_build_m, R::cache);
    field("skin_at_build_m", w.skin_at_build_m, R::cache);
    field("neighbours_dirty", w.neighbours_dirty, R::cache);
    field("neighbour_builds", w.neighbour_builds, R::cache);
}

} // namespace wiredem::engine
