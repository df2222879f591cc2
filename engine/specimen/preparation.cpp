#include "specimen/preparation.hpp"

#include "integrate/clumps.hpp"

#include "contact/geometry.hpp"
#include "core/format.hpp"
#include "core/result.hpp"
#include "scene.hpp"
#include "specimen/packing.hpp"
#include "timestep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>

namespace wiredem::engine {
namespace {

constexpr double assumed_packing_fraction = 0.58; // for the fill-height estimate while pouring
// Grains are placed at random in the pouring zone, which they fill to about
// 0.3 before no more fit, and leave it at the entry speed; the pile then rises
// at most 0.3/0.58 ≈ 0.5 of that speed. Entering at ≥ 2.5 × the fill rate
// keeps the pour on time (measured: at 0.3 m/s with entry at 0.5 m/s the
// laying ended 34 % late).
constexpr double pour_speed_per_fill_rate = 2.5;
// A node the nozzle pushes out through grains starts this fraction of a
// segment length beyond the wire's end.
constexpr double push_out_start = 0.05;

/// Speed at which grains enter the pouring zone [m/s].
double pour_entry_speed_m_per_s(const PreparationSpec& spec)
{
    return std::max(spec.pour_speed_m_per_s, pour_speed_per_fill_rate * spec.fill_rate_m_per_s);
}

/// Which grains rest on something this step (touch another body or a wall):
/// the pile, as opposed to grains still falling.
std::vector<std::uint8_t> grains_in_pile(const World& w)
{
    std::vector<std::uint8_t> in(w.of(BodyKind::grain).size(), 0);
    const ContactList& c = w.contacts;
    for (std::size_t p = 0; p < c.size(); ++p) { // body pairs and body–wall contacts
        if (!c.touching[p]) continue;
        if (c.first[p].kind() == BodyKind::grain) in[c.first[p].index()] = 1;
        if (c.second[p].kind() == BodyKind::grain) in[c.second[p].index()] = 1;
    }
    return in;
}

/// Highest top (z + r) of the grains in the pile [m]; 0 on an empty floor.
double pile_top_m(const World& w, const std::vector<std::uint8_t>& in_pile)
{
    const TranslationalState& g = w.of(BodyKind::grain);
    double top = 0.0;
    for (std::size_t i = 0; i < in_pile.size(); ++i)
        if (in_pile[i]) top = std::max(top, g.x[0][i].z() + g.radius_m[i]);
    return top;
}

/// Height at which a sphere of radius `r` lowered along the vertical through
/// `at` comes to rest on the pile: on a grain in the pile, on laid wire (all
/// but the newest `own_nodes` nodes, which hang from the nozzle) or on the
/// bottom plate [m].
double resting_height_m(const World& w, const Vec3& at, double r, const std::vector<std::uint8_t>& in_pile,
    std::size_t own_nodes)
{
    double z = r;
    for (int k = 0; k < 2; ++k) { // grains, wire
        const TranslationalState& b = w.bodies[k];
        const std::size_t n = k == 0 ? in_pile.size() : b.size() - std::min(b.size(), own_nodes);
        for (std::size_t i = 0; i < n; ++i) {
            if (k == 0 && !in_pile[i]) continue;
            const Vec3& x = b.x[0][i];
            const double reach = b.radius_m[i] + r;
            const double d2 = (x.x() - at.x()) * (x.x() - at.x()) + (x.y() - at.y()) * (x.y() - at.y());
            if (d2 < reach * reach) z = std::max(z, x.z() + std::sqrt(reach * reach - d2));
        }
    }
    return z;
}

/// The nozzle: walks the pattern at constant path speed, follows the top of
/// the pile under it, and lays a wire node on the pile every segment length.
class Nozzle {
public:
    /// A nozzle whose state (height, path position, last node's) is `state`,
    /// kept there as it moves: part of the preparation's driver state.
    Nozzle(const PreparationSpec& spec, PreparationDriverState::NozzleState& state)
        : path_(spec.pattern, 2.5 * spec.wire.radius_m), spec_(spec), st_(state)
    {
        path_.continue_from(st_.path_integration);
    }

    /// Advances by δt, moving its height towards `target_z_m` (the top of the
    /// pile under it) at most v_z^w, and lays a node each time it has
    /// travelled a segment length along its path. The node is born at rest:
    /// the nozzle feeds wire backwards at its own speed, so laid wire does not
    /// move over the ground (docs/model.md: a node born with the nozzle's
    /// velocity drags the chain's free end along the path, or upwards, until
    /// the chain runs into itself).
    void advance(World& w, double dt, double target_z_m)
    {
        const double dz_max = spec_.pattern.nozzle_rise_speed_m_per_s * dt;
        st_.z_m += std::clamp(target_z_m - st_.z_m, -dz_max, dz_max);
        st_.path_m += path_.speed_m_per_s() * dt;
        // A node each time the nozzle has travelled one segment length along
        // its path (so the wire is laid at the path speed ω R_a), placed one
        // segment length from the wire's current end towards the nozzle: the
        // new segment is born unstrained even when the laid wire has moved
        // (it springs back towards its rest angles: ζ₀ = 0 for the model
        // spec's elastic wire, the plastically formed ζ₀ otherwise).
        const Vec3 here = position();
        const auto& x = w.of(BodyKind::wire).x[0];
        const double l = spec_.wire.segment_length_m;
        if (x.empty()) {
            lay(w, here);
            st_.last_node_path_m = st_.path_m;
            return;
        }
        if (coming_out(w)) {
            grow_end(w, dt, here);
            return;
        }
        if (st_.path_m - st_.last_node_path_m < l) return;
        // Fed late where the way was blocked, the wire catches up one node
        // per step. Two segments late, the nozzle looks round its grains too
        // and, with no way clear, pushes the wire out through them.
        const bool late = st_.path_m - st_.last_node_path_m >= 2.0 * l;
        if (const std::optional<Vec3> at = clear_spot(w, here, late)) {
            lay(w, *at);
            st_.last_node_path_m += l;
        } else if (late) {
            push_out(w, here);
            st_.last_node_path_m += l;
        }
    }
    /// Once it has stopped laying, the nozzle still holds the wire's end but
    /// pays wire out (or takes it in) as the column under it compacts: the
    /// end stays on the line of the last segment, at its rest length from the
    /// node before it. Pinned where it was laid instead, the end of 10 m of
    /// helix ended 7 mm above the compacted pile with its last segment
    /// stretched 4.3 times, and released, it whipped at 30 m/s and blew the
    /// column up (measured on a 2000-grain column).
    void pay_out(World& w, double dt) const
    {
        TranslationalState& wire = w.of(BodyKind::wire);
        const std::size_t n = wire.size();
        if (n < 2) return;
        if (coming_out(w)) { // a node still being pushed out comes out along its line
            grow_end(w, dt, wire.x[0][n - 1] + (wire.x[0][n - 1] - wire.x[0][n - 2]));
            return;
        }
        if (is_dynamic(wire, n - 1)) return; // not held
        const Vec3 along = wire.x[0][n - 1] - wire.x[0][n - 2];
        const double length = along.norm();
        if (!(length > 0.0)) return;
        // Kinematic for the next step, with the velocity that takes it there.
        const auto end = static_cast<std::uint32_t>(n - 1);
        set_motion(w, {BodyKind::wire, end}, Motion::kinematic);
        wire.x[1][end] = wire.x[0][n - 2] + along * (spec_.wire.segment_length_m / length) - wire.x[0][end];
    }
    /// Lets go of the wire's end (and of the node before it, held while the
    /// end was pushed out): both ends free.
    static void release_end(World& w)
    {
        TranslationalState& wire = w.of(BodyKind::wire);
        for (std::size_t i = first_end_node(wire); i < wire.size(); ++i)
            if (!is_dynamic(wire, i)) set_motion(w, {BodyKind::wire, static_cast<std::uint32_t>(i)}, Motion::dynamic);
    }
    /// The first of the nodes the nozzle may hold: the end, and the node
    /// before it while the end is pushed out.
    [[nodiscard]] static std::size_t first_end_node(const TranslationalState& wire)
    {
        return wire.size() - std::min<std::size_t>(wire.size(), 2);
    }
    /// Whether the lid, coming down, has reached a node of the wire's end
    /// that the nozzle still holds. A held node is never among a wall's
    /// contacts (neither moves by its forces: update_neighbours), so the lid
    /// would pass into it, and the end, released under the lid, be flung out
    /// of it (measured: released 0.35 mm deep in the lid, 75 N, the end at
    /// 1.7 m/s when the column was declared settled).
    [[nodiscard]] static bool lid_reaches_held_end(const World& w, const Wall& lid)
    {
        const TranslationalState& wire = w.of(BodyKind::wire);
        for (std::size_t i = first_end_node(wire); i < wire.size(); ++i)
            if (!is_dynamic(wire, i) && wall_gap(lid, wire.x[0][i]).gap_m <= wire.radius_m[i]) return true;
        return false;
    }
    [[nodiscard]] double z_m() const { return st_.z_m; }
    [[nodiscard]] Vec3 position() const
    {
        const Vec3 at = path_.at(st_.path_m) + Vec3(0, 0, st_.z_m);
        st_.path_integration = path_.integration();
        return at;
    }
    /// Path length travelled so far [m].
    [[nodiscard]] double path_m() const { return st_.path_m; }

private:
    /// A body near the wire's end that a new node must not overlap: its
    /// centre and r_i + r_w.
    struct Obstacle {
        Vec3 x;
        double reach_m;
    };
    /// The grains and wire nodes (but the wire's last two: its neighbours
    /// along the chain, which never touch it) that a node one segment length
    /// from the end at `end` could overlap.
    [[nodiscard]] std::vector<Obstacle> obstacles_near(const World& w, const Vec3& end) const
    {
        const double l = spec_.wire.segment_length_m, r = spec_.wire.radius_m;
        std::vector<Obstacle> near;
        for (int k = 0; k < 2; ++k) {
            const TranslationalState& b = w.bodies[k];
            const std::size_t n = k == 0 ? b.size() : b.size() - std::min<std::size_t>(b.size(), 2);
            for (std::size_t i = 0; i < n; ++i) {
                const double reach = b.radius_m[i] + r;
                const double within = (l + reach) * (1.0 + 1e-9); // a margin over the rounding of the test below
                if ((b.x[0][i] - end).squaredNorm() < within * within) near.push_back({b.x[0][i], reach});
            }
        }
        return near;
    }
    /// No obstacle overlaps a node at `at`.
    [[nodiscard]] static bool is_clear(const std::vector<Obstacle>& near, const Vec3& at)
    {
        return std::none_of(near.begin(), near.end(), [&](const Obstacle& o) { return (o.x - at).squaredNorm() < o.reach_m * o.reach_m; });
    }
    /// Where the next node goes: one segment length from the wire's end,
    /// towards the nozzle at `here`, or, where a grain or earlier wire is in
    /// the way, turned as little as needed (upwards first, then sideways, at
    /// most 60° to either side) to overlap nothing: the wire comes out of the
    /// nozzle onto the pile, never into a grain. Born inside a grain, the held
    /// node pushed it out with the Hertz force of an overlap of up to 1.2 mm,
    /// and grains flew off at 1–3 m/s (measured; one went 0.4 m up and,
    /// falling back faster than the time step allows, blew the run up).
    /// `late`: the nozzle is two segments behind; then any way round the
    /// grains that bends the wire at its end by at most 90° will do (see
    /// round_the_grains). Nothing when every direction looked at is blocked.
    [[nodiscard]] std::optional<Vec3> clear_spot(const World& w, const Vec3& here, bool late) const
    {
        const double l = spec_.wire.segment_length_m;
        const auto& wire = w.of(BodyKind::wire).x[0];
        const Vec3& end = wire.back();
        const std::vector<Obstacle> near = obstacles_near(w, end);
        const Vec3 reach = here - end;
        const Vec3 flat(reach.x(), reach.y(), 0.0);
        const double horizontal = flat.norm();
        const Vec3 h = horizontal > 1e-9 * l ? Vec3(flat / horizontal) : Vec3::UnitX();
        const Vec3 side = Vec3::UnitZ().cross(h);
        const double start = std::atan2(reach.z(), horizontal);
        constexpr int turns = 18;                    // elevation steps of at most 5°
        constexpr double azimuths[] = {0.0, 0.35, -0.35, 0.7, -0.7, 1.05, -1.05}; // 0, ±20°, ±40°, ±60°
        for (double az : azimuths)
            for (int k = 0; k <= turns; ++k) {
                const double e = start + (0.5 * std::numbers::pi - start) * k / turns;
                const Vec3 dir = std::cos(e) * (std::cos(az) * h + std::sin(az) * side) + std::sin(e) * Vec3::UnitZ();
                const Vec3 at = end + l * dir;
                if (is_clear(near, at)) return at;
            }
        if (!late) return std::nullopt;
        return round_the_grains(near, wire, here);
    }
    /// The search of a late nozzle: every direction from the wire's end
    /// (about every 5°), least turned from the way to the nozzle at `here`
    /// first, that bends the wire at its end by at most 90°. In a small
    /// column grains landing round the held end cover it; the search above,
    /// which looks only upwards and ahead, then found no way, and the nozzle
    /// stopped laying for good (docs/model.md: a third of the seeds of the
    /// 300-grain test column lost most of their wire).
    [[nodiscard]] std::optional<Vec3> round_the_grains(
        const std::vector<Obstacle>& near, const std::vector<Vec3>& wire, const Vec3& here) const
    {
        const double l = spec_.wire.segment_length_m;
        const Vec3& end = wire.back();
        const Vec3 ahead = towards(end, here);
        Vec3 up = Vec3::UnitZ() - Vec3::UnitZ().dot(ahead) * ahead;
        up = up.norm() > 1e-6 ? Vec3(up.normalized()) : Vec3(ahead.unitOrthogonal());
        const Vec3 across = ahead.cross(up);
        const Vec3 last = wire.size() >= 2 ? towards(wire[wire.size() - 2], end) : ahead;
        for (const Direction& d : directions()) {
            const Vec3 dir = d.ahead * ahead + d.up * up + d.across * across;
            if (dir.dot(last) < 0.0) continue; // a bend of more than 90°
            const Vec3 at = end + l * dir;
            if (is_clear(near, at)) return at;
        }
        return std::nullopt;
    }
    /// A unit vector in the frame (ahead, up, across).
    struct Direction {
        double ahead, up, across;
    };
    /// Directions about every 5° over the sphere, by the angle θ from ahead
    /// (0 to 180°), and at each θ from up round to either side alternately.
    static const std::vector<Direction>& directions()
    {
        static const std::vector<Direction> table = [] {
            std::vector<Direction> t;
            constexpr int polar_steps = 36; // 5°
            for (int i = 0; i <= polar_steps; ++i) {
                const double theta = std::numbers::pi * i / polar_steps;
                const int around = std::max(1, static_cast<int>(std::lround(72.0 * std::sin(theta))));
                for (int k = 0; k < around; ++k) {
                    const int j = (k + 1) / 2; // 0, 1, 1, 2, 2, …: up, then either side
                    const double phi = (k % 2 == 1 ? 1.0 : -1.0) * 2.0 * std::numbers::pi * j / around;
                    t.push_back({std::cos(theta), std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi)});
                }
            }
            return t;
        }();
        return table;
    }
    /// The unit vector from `a` towards `b` (up when they coincide).
    [[nodiscard]] static Vec3 towards(const Vec3& a, const Vec3& b)
    {
        const Vec3 d = b - a;
        const double n = d.norm();
        return n > 0.0 ? Vec3(d / n) : Vec3::UnitZ();
    }

    /// Whether a node is being pushed out: the wire's end kinematic, the node
    /// before it still held. Read from the World, so a saved preparation
    /// continues the push.
    [[nodiscard]] static bool coming_out(const World& w)
    {
        const TranslationalState& wire = w.of(BodyKind::wire);
        const std::size_t n = wire.size();
        return n >= 2 && wire.motion[n - 1] == Motion::kinematic && !is_dynamic(wire, n - 2);
    }
    /// With no way clear, the nozzle pushes the wire out through the grains
    /// round its end: a node is born just beyond the end (0.05 l, towards the
    /// nozzle at `here`) and grows out to a segment length (grow_end), the
    /// end held meanwhile, so the grains are pushed aside at the nozzle's
    /// rise speed, not at once. (At the path speed ω R_a, measured: two
    /// preparations of six blew up.)
    void push_out(World& w, const Vec3& here) const
    {
        TranslationalState& wire = w.of(BodyKind::wire);
        const Vec3 end = wire.x[0].back();
        const std::uint32_t id = append_wire_node(w, end + push_out_start * spec_.wire.segment_length_m * towards(end, here));
        set_motion(w, {BodyKind::wire, id}, Motion::kinematic); // at rest: x₁ = 0 until grow_end
    }
    /// Moves the node being pushed out for the next step: towards `towards_m`
    /// from the held node before it, its length up to l, by at most v_z^w δt.
    /// At its full length it is held where it is and the node before it let go.
    void grow_end(World& w, double dt, const Vec3& towards_m) const
    {
        TranslationalState& wire = w.of(BodyKind::wire);
        const std::size_t n = wire.size();
        const double l = spec_.wire.segment_length_m;
        const Vec3& base = wire.x[0][n - 2];
        const Vec3& at = wire.x[0][n - 1];
        const double length = (at - base).norm();
        const auto end = static_cast<std::uint32_t>(n - 1);
        if (length >= (1.0 - 1e-9) * l) {
            set_motion(w, {BodyKind::wire, end}, Motion::fixed);
            set_motion(w, {BodyKind::wire, static_cast<std::uint32_t>(n - 2)}, Motion::dynamic);
            return;
        }
        const double step = spec_.pattern.nozzle_rise_speed_m_per_s * dt;
        const Vec3 target = base + std::min(l, length + step) * towards(base, towards_m);
        Vec3 move = target - at;
        if (const double m = move.norm(); m > step) move *= step / m;
        wire.x[1][end] = move;
    }
    /// Appends a node and holds it where it was laid until the next one: the
    /// wire's end is inside the nozzle, so it cannot whip. A wire laid along
    /// a curve stores ½ k_rot ζ² per joint (straight rest shape, the model
    /// spec §3); with a free end that energy is released at the end of the
    /// chain as a whip of tens of m/s. Held, each joint can only relax
    /// against its neighbours and the grains, short-wave motion that the
    /// wire's own damping absorbs.
    static void lay(World& w, const Vec3& at)
    {
        release_end(w);
        const std::uint32_t id = append_wire_node(w, at);
        set_motion(w, {BodyKind::wire, id}, Motion::fixed);
    }

    NozzlePath path_;
    const PreparationSpec& spec_;
    PreparationDriverState::NozzleState& st_;
};

} // namespace

namespace {

/// The settling energy of the grains `counts` keeps (counts(centre), a
/// clump's by its centre of mass) and of the wire, and their count. A clump's
/// member spheres are asked by their own centres, which is harmless: they
/// weigh nothing and count as no grain, their clump is asked once.
template <class Counts>
SettlingEnergy settling_energy(const World& w, double wire_mass_scale, Counts&& counts)
{
    SettlingEnergy out;
    double& e = out.energy_j;
    const TranslationalState& g = w.of(BodyKind::grain);
    const ClumpState& c = w.clumps;
    const double inv_dt2 = 1.0 / (w.dt_s * w.dt_s);
    for (std::size_t i = 0; i < g.size(); ++i) {
        if (!counts(g.x[0][i])) continue;
        out.grains += c.is_member(i) ? 0 : 1;
        e += 0.5 * g.mass_kg[i] * g.x[1][i].squaredNorm() * inv_dt2;
        const Vec3 omega = angular_velocity_rad_per_s(w, static_cast<std::uint32_t>(i));
        const double inv_i = w.grain_rotation.inv_inertia_per_kg_m2[i];
        if (inv_i > 0.0) e += 0.5 * omega.squaredNorm() / inv_i;
    }
    if (!c.empty()) { // their spheres weigh nothing
        double clumps = 0.0;
        for (std::size_t k = 0; k < c.size(); ++k)
            if (counts(c.x[0][k])) clumps += clump_kinetic_energy_j(w, k), ++out.grains;
        e += clumps;
    }
    const TranslationalState& n = w.of(BodyKind::wire);
    for (std::size_t i = 0; i < n.size(); ++i)
        if (is_dynamic(n, i)) e += 0.5 * n.mass_kg[i] / wire_mass_scale * n.x[1][i].squaredNorm() * inv_dt2;
    return out;
}

} // namespace

double settling_energy_j(const World& w, double wire_mass_scale)
{
    return settling_energy(w, wire_mass_scale, [](const Vec3&) { return true; }).energy_j;
}

SettlingEnergy settling_energy_of(
    const World& w, double wire_mass_scale, const std::function<bool(const Vec3& centre_m)>& counts)
{
    return settling_energy(w, wire_mass_scale, counts);
}

void set_weights(World& w, double density_scale, double wire_mass_scale, double weight_factor)
{
    const Vec3 g(0.0, 0.0, -standard_gravity_m_per_s2);
    w.gravity_m_per_s2 = g * (weight_factor / density_scale);
    w.gravity_acts[static_cast<int>(BodyKind::wire)] = false;
    const TranslationalState& wire = w.of(BodyKind::wire);
    w.point_loads.clear();
    w.point_loads.reserve(wire.size());
    const double per_mass = weight_factor / (density_scale * wire_mass_scale);
    for (std::uint32_t i = 0; i < wire.size(); ++i)
        w.point_loads.set(BodyRef(BodyKind::wire, i), wire.mass_kg[i] * per_mass * g);
}

namespace {

/// What a preparation sets up before its first step and never changes: the
/// empty column (plates, rigid membrane, mould, weights, δt) and the indices
/// the phases refer to. Built again when a preparation continues (the World
/// then comes from the checkpoint; the rest is the same for the same spec).
struct Column {
    World world;
    std::uint8_t grain_mat = 0;
    std::uint8_t plate_mat = 0;
    std::size_t mould_wall = 0;
    bool wire_touches_membrane = false; ///< wire–membrane contact, off while the mould stands
    StableStep step;                    ///< the pour's stable step (grains, wire, impacts)
};

Column empty_column(const PreparationSpec& spec)
{
    const double R = spec.membrane_radius_m;
    const double r_max = largest_grain_radius_m(spec);
    const double r_m = spec.membrane.contact_radius_m;
    const bool with_wire = spec.pattern.pattern != PatternKind::none;
    Column c;
    World& w = c.world;
    w.integrator = spec.integrator;
    w.contact = spec.contact;
    Material grain = spec.grain;
    grain.density_kg_per_m3 *= spec.density_scale;
    c.grain_mat = add_material(w, grain);
    c.plate_mat = add_material(w, spec.plate);
    add_wall(w, make_plate(0.0, +1.0, c.plate_mat));
    WireSpec wire = spec.wire;
    wire.density_scale = spec.density_scale * spec.wire_mass_scale;
    configure_wire(w, wire);
    MembraneSpec membrane = spec.membrane;
    membrane.radius_m = R;
    membrane.height_m = spec.membrane_height_m;
    membrane.base_z_m = 0.0;
    membrane.density_scale = spec.density_scale; // the wire alone takes wire_mass_scale
    build_membrane(w, membrane);
    set_membrane_rigid(w, true);
    // The mould lies on the inner surface of the membrane's node spheres: a
    // wire node held by it is at most touching them when it goes and
    // wire–membrane contact comes on. (At R + r_m, wire nodes sat in the
    // spheres' plane, up to r_w + r_m deep in them when the contact came on.)
    c.mould_wall = add_wall(w, make_cylinder(R - r_m, c.plate_mat));
    // While the mould holds the wire, the wire does not touch the rigid
    // membrane: a node pressed into a hole of the mesh against the mould was
    // squeezed from four sides (overlaps far beyond the time step's reference,
    // measured: examples/small.json blew up).
    c.wire_touches_membrane = w.kinds_interact[1][2];
    set_kinds_interact(w, BodyKind::wire, BodyKind::membrane, false);
    // Weights scaled like the masses while pouring (see preparation.hpp).
    set_weights(w, spec.density_scale, spec.wire_mass_scale, spec.density_scale);

    // The time step must hold for the wire and the grains before they exist:
    // probe with one of each.
    World probe = w;
    add_smallest_grain(probe, spec, c.grain_mat);
    if (with_wire) {
        append_wire_node(probe, Vec3(0, 0, 2));
        append_wire_node(probe, Vec3(0, 0, 2 + spec.wire.segment_length_m));
    }
    // Fastest impact: entering the zone at the pour speed, then falling
    // through the zone and the gap above the pile (≤ 12 r_max).
    const double impact = pour_entry_speed_m_per_s(spec) + std::sqrt(2.0 * w.gravity_m_per_s2.norm() * 12.0 * r_max);
    c.step = stable_time_step(probe, impact);
    w.dt_s = spec.time_step_s > 0.0 ? spec.time_step_s : c.step.auto_s;
    return c;
}

} // namespace

std::optional<std::string> preparation_error(const PreparationSpec& spec)
{
    const double R = spec.membrane_radius_m;
    const double r_m = spec.membrane.contact_radius_m;
    const bool with_wire = spec.pattern.pattern != PatternKind::none;
    if (with_wire && !(pattern_reach_m(spec.pattern) < wire_reach_limit_m(spec)))
        return "the wire pattern reaches " + std::to_string(pattern_reach_m(spec.pattern) * 1e3)
             + " mm from the axis; it must stay below the membrane radius less the membrane nodes' contact radius, "
             + "the wire's radius and the clearance: " + std::to_string(R * 1e3) + " - " + std::to_string(r_m * 1e3)
             + " - " + std::to_string(spec.wire.radius_m * 1e3) + " - " + std::to_string(spec.clearance_m * 1e3)
             + " = " + std::to_string(wire_reach_limit_m(spec) * 1e3) + " mm";
    if (with_wire && !(wire_laying_height_m(spec) > 0.0))
        return "the grains fill about " + std::to_string(estimated_fill_height_m(spec) * 1e3)
             + " mm, not above the " + std::to_string(wire_cover_height_m(spec) * 1e3)
             + " mm of grains poured over the wire's end: the nozzle would lay no wire";
    if (!(spec.fill_rate_m_per_s > 0.0)) return std::string("the fill rate must be positive");
    if (with_wire && spec.fill_rate_m_per_s > max_fill_rate_per_rise_speed * spec.pattern.nozzle_rise_speed_m_per_s)
        return "the fill rate " + std::to_string(spec.fill_rate_m_per_s) + " m/s is too fast for the nozzle, which "
             + "rises at most " + std::to_string(spec.pattern.nozzle_rise_speed_m_per_s)
             + " m/s and must follow the pile's uneven top: at most 0.6 times that";
    if (required_membrane_height_m(spec) > spec.membrane_height_m)
        return "the grains fill about " + std::to_string(estimated_fill_height_m(spec) * 1e3)
             + " mm; the membrane must be taller than that plus room for pouring ("
             + std::to_string(required_membrane_height_m(spec) * 1e3) + " mm)";
    return std::nullopt;
}

Result<PreparationReport, std::string> prepare_specimen(Simulation& sim, const PreparationSpec& spec, const RunControl& control)
{
    return prepare_specimen(sim, spec, control, {});
}

Result<PreparationReport, std::string> prepare_specimen(
    Simulation& sim, const PreparationSpec& spec, const RunControl& control, PreparationContinuation continuation)
{
    const auto wall_start = std::chrono::steady_clock::now();
    const double R = spec.membrane_radius_m;
    const double r_max = largest_grain_radius_m(spec);
    const double r_m = spec.membrane.contact_radius_m;
    const bool with_wire = spec.pattern.pattern != PatternKind::none;
    if (auto e = preparation_error(spec)) return Err(*e);
    const double fill_height = estimated_fill_height_m(spec);
    const double wire_cover_m = wire_cover_height_m(spec);
    const double entry_speed = pour_entry_speed_m_per_s(spec);
    Column column = empty_column(spec);
    if (column.step.overdamped()) return Err(overdamped_error(column.step, column.world.contact.normal_damping_s));
    // An explicit step is held to the pour's bound (its contacts' damping at
    // the fastest impact), as the box preparation and the tests hold theirs;
    // the door's estimate leaves a restitution's damping out (api/derived.hpp).
    if (spec.time_step_s > column.step.critical_s)
        return Err("the time step (engine.time_step_s) " + format_number(spec.time_step_s) + " s exceeds the stable limit "
                   + format_number(column.step.critical_s) + " s of the pour, set by the " + column.step.limited_by
                   + " at its fastest impact (\"auto\" would use " + format_number(column.step.auto_s) + " s)");
    World& w = sim.world;
    PreparationDriverState st;
    const bool continuing = continuation.from.has_value();
    if (continuing) {
        st = std::move(*continuation.from); // sim.world is the World saved with it
    } else {
        w = std::move(column.world);
        st.rng_state = spec.seed;
        st.nozzle.z_m = spec.wire.radius_m;
        st.nozzle_target_m = spec.wire.radius_m;
    }
    const double dt = w.dt_s;

    const double pour_time = fill_height / spec.fill_rate_m_per_s;
    const double grains_per_s = static_cast<double>(spec.grain_count) / pour_time;
    const double zone_height = 4.0 * r_max;
    const double batch_interval = zone_height / entry_speed;
    const double pour_radius = R - r_m - r_max - 0.05 * r_max; // grain centres inside the membrane spheres
    Nozzle nozzle(spec, st.nozzle);
    // Wire nodes within the nozzle's reach (2 r_w) along the chain behind it, + 1.
    const auto own_nodes = static_cast<std::size_t>(std::ceil(3.0 * spec.wire.radius_m / spec.wire.segment_length_m)) + 1;
    const auto expected_steps = static_cast<std::uint64_t>((pour_time + 0.1) / dt);
    const std::optional<GrainSizeDistribution> sizes = spec.grain_sizes
        ? std::optional<GrainSizeDistribution>(std::in_place, *spec.grain_sizes) : std::nullopt;
    auto fill_now = [&] { return st.poured_volume_m3 / (assumed_packing_fraction * std::numbers::pi * R * R); };

    // One step, the nozzle paying out first. A checkpoint may be taken before
    // it (not before the first step of this run: that state is the one the
    // run started from), also when the run is about to be cancelled.
    bool first_of_run = true;
    auto step_once = [&]() -> std::string {
        if (continuation.between_steps && !first_of_run) {
            const double this_run_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
            st.wall_time_s += this_run_s;
            continuation.between_steps(w, st);
            st.wall_time_s -= this_run_s;
        }
        first_of_run = false;
        if (control.cancel && control.cancel->load()) return "cancelled";
        if (st.laid_all) nozzle.pay_out(w, w.dt_s);
        if (sim.step().blew_up)
            return blow_up_error(w.dt_s, "after " + std::to_string(st.steps + 1) + " steps of the preparation, at t = "
                                             + format_number(w.time_s) + " s");
        ++st.steps;
        if (control.progress && control.progress_every && st.steps % control.progress_every == 0)
            control.progress(st.steps, std::max(expected_steps, st.steps));
        return {};
    };

    // Pouring and laying, before a step: grains due are poured above the pile
    // and the nozzle moves on.
    auto pour_and_lay = [&] {
        // The pile (grains touching something, not those still falling),
        // looked at every 10 steps (grains move ~r/100 in between).
        const bool look = st.steps % 10 == 0;
        std::vector<std::uint8_t> in_pile;
        if (look) {
            in_pile = grains_in_pile(w);
            st.pile_top_m = pile_top_m(w, in_pile);
        }
        if (w.time_s >= st.next_batch_s) {
            st.owed_grains += grains_per_s * batch_interval;
            // Above the pile, whichever is higher: the poured volume's fill
            // height, the pile's top or the nozzle.
            const double zone_low = std::max({fill_now(), st.pile_top_m, nozzle.z_m()}) + 3.0 * r_max;
            const int attempts = static_cast<int>(std::ceil(st.owed_grains)) * 20;
            SplitMix64 rng(st.rng_state);
            // From a curve, a grain keeps its size until it is placed: a
            // size drawn afresh at every attempt would favour the small
            // grains, which find a free spot more often. (The spread draws
            // afresh, as it always has.) A size still unplaced when the
            // batch's attempts run out is dropped.
            double curve_radius = 0.0;
            for (int a = 0; a < attempts && st.owed_grains >= 1.0 && grain_body_count(w) < spec.grain_count; ++a) {
                if (sizes && curve_radius == 0.0) curve_radius = 0.5 * sizes->diameter_at_number_fraction(rng.uniform());
                const double radius = sizes ? curve_radius
                    : spec.grain_radius_m * (1.0 + spec.grain_radius_spread * (2.0 * rng.uniform() - 1.0));
                const double rho = pour_radius * std::sqrt(rng.uniform()), phi = 2.0 * std::numbers::pi * rng.uniform();
                const Vec3 x(rho * std::cos(phi), rho * std::sin(phi), zone_low + zone_height * rng.uniform());
                // A clump is placed where its bounding sphere is free, turned at random.
                const std::optional<ClumpBody> clump
                    = spec.grain_shape ? std::optional<ClumpBody>(scaled_clump(*spec.grain_shape, radius)) : std::nullopt;
                const double extent = clump ? clump->bounding_radius_m() : radius;
                bool free = true;
                for (int k = 0; k < 2 && free; ++k) {
                    const TranslationalState& b = w.bodies[k];
                    for (std::size_t i = b.size(); i-- > 0 && free;) // the newest bodies are the likeliest neighbours
                        free = (b.x[0][i] - x).norm() >= extent + b.radius_m[i] + 0.1 * r_max;
                }
                if (!free) continue;
                if (clump) {
                    const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
                    add_clump(w, *clump, x, uniform_orientation(u1, u2, u3), column.grain_mat, Vec3(0, 0, -entry_speed));
                } else {
                    add_grain(w, x, radius, column.grain_mat, Vec3(0, 0, -entry_speed));
                }
                curve_radius = 0.0;
                st.poured_volume_m3 += 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
                st.owed_grains -= 1.0;
            }
            st.rng_state = rng.state();
            st.next_batch_s += batch_interval;
        }
        // The last grain diameter of the fill is poured over the wire: the
        // nozzle stops there, so that its last turn is buried too.
        st.laid_all = with_wire && fill_now() >= fill_height - wire_cover_m;
        if (with_wire && !st.laid_all) {
            // The nozzle follows the top of the pile under it (grains that
            // have landed, and earlier wire), so that each node is laid on the
            // pile and the grains that follow bury it.
            if (look) st.nozzle_target_m = resting_height_m(w, nozzle.position(), spec.wire.radius_m, in_pile, own_nodes);
            nozzle.advance(w, dt, st.nozzle_target_m);
            if (w.point_loads.size() != w.of(BodyKind::wire).size())
                set_weights(w, spec.density_scale, spec.wire_mass_scale, spec.density_scale);
        }
    };

    // Settling: the kinetic energy per grain, with the masses scaled by s only
    // (the nodes' extra inertia M does not count), below the threshold × s,
    // looked at every check_every steps. Whether it settled, once decided.
    const auto check_every = static_cast<std::uint64_t>(std::max(1.0, 1e-3 / dt));
    auto settling_ended = [&]() -> std::optional<bool> {
        if (st.steps % check_every != 0) return std::nullopt;
        const double ke = settling_energy_j(w, spec.wire_mass_scale);
        if (ke / static_cast<double>(grain_body_count(w)) < spec.settle_kinetic_energy_per_grain_j * spec.density_scale)
            return true;
        if (w.time_s > spec.max_time_s) return false;
        return std::nullopt;
    };

    // Everything between two steps: the checks after the step just taken
    // (`stepped`: there was one), the phases that end there, and the work
    // before the next step. Returns whether a step follows (none: the
    // preparation is done, or failed with `error`). Each phase's work happens
    // here in the order of the straight sequence (preparation.hpp), so a
    // state saved before a step continues as the sequence would.
    std::string error;
    auto until_next_step = [&](bool stepped) -> bool {
        for (;;) {
            switch (st.phase) {
            case PreparationPhase::pouring:
                if (grain_body_count(w) >= spec.grain_count) {
                    // The nozzle stops laying with the pour, if the fill has
                    // not stopped it before (a wire cover of zero: the fill
                    // height is reached only by the last grain). Still laying,
                    // it would leave its end held as it was, a node being
                    // pushed out drifting on at v_z^w through the settling and
                    // into the lid.
                    st.laid_all = with_wire;
                    st.phase = PreparationPhase::settling;
                    stepped = false;
                    continue;
                }
                if (w.time_s > spec.max_time_s) {
                    error = "preparation exceeded max_preparation_time_s while pouring";
                    return false;
                }
                pour_and_lay();
                return true;
            case PreparationPhase::settling: {
                const std::optional<bool> settled = stepped ? settling_ended() : std::nullopt;
                if (!settled) return true;
                st.settled_before_lid = *settled;
                remove_wall(w, column.mould_wall); // the mould goes before the lid
                set_kinds_interact(w, BodyKind::wire, BodyKind::membrane, column.wire_touches_membrane);
                // Lower the top plate until it rests on the grains: wire
                // standing out of the pile (a laid coil springs back towards
                // straight) is pushed back in on the way down. It starts
                // above the highest body; a plate below a grain's centre
                // without touching a grain has gone through the pile.
                double top = 0.0;
                for (int k = 0; k < 2; ++k)
                    for (std::size_t i = 0; i < w.bodies[k].size(); ++i)
                        top = std::max(top, w.bodies[k].x[0][i].z() + w.bodies[k].radius_m[i]);
                st.top_plate_wall = add_wall(w, make_plate(top + 0.5 * r_max, -1.0, column.plate_mat));
                w.walls[st.top_plate_wall].velocity_m_per_s = Vec3(0, 0, -spec.plate_speed_m_per_s);
                st.phase = PreparationPhase::lowering_lid;
                stepped = false;
                continue;
            }
            case PreparationPhase::lowering_lid:
            case PreparationPhase::following_lid: {
                Wall& lid = w.walls[st.top_plate_wall];
                // Compared with the grains' centres now: a grain still
                // falling away from the plate is no reason to stop.
                const auto& grains = w.of(BodyKind::grain).x[0];
                if (stepped && std::any_of(grains.begin(), grains.end(), [&](const Vec3& x) { return x.z() > lid.point_m.z(); })) {
                    error = "the top plate went through the pile without touching it";
                    return false;
                }
                // The wire's end leaves the nozzle once the lid reaches it,
                // if that comes before the pile, so that the lid presses on
                // a free end instead of passing into a held one.
                if (st.phase == PreparationPhase::lowering_lid && Nozzle::lid_reaches_held_end(w, lid))
                    Nozzle::release_end(w);
                if (!w.contacts.wall_touches(st.top_plate_wall, BodyKind::grain)) return true;
                lid.velocity_m_per_s.setZero();
                if (st.phase == PreparationPhase::following_lid) return false; // done
                // The wire's end leaves the nozzle (the model spec §3: both
                // ends free) under the lid, the column settles again
                // (measured: ~1 mm lower, the wire and the grains moved by the
                // released end), and the lid follows it.
                Nozzle::release_end(w);
                st.phase = PreparationPhase::settling_under_lid;
                stepped = false;
                continue;
            }
            case PreparationPhase::settling_under_lid: {
                const std::optional<bool> settled = stepped ? settling_ended() : std::nullopt;
                if (!settled) return true;
                st.settled_under_lid = *settled;
                w.walls[st.top_plate_wall].velocity_m_per_s = Vec3(0, 0, -spec.plate_speed_m_per_s);
                st.phase = PreparationPhase::following_lid;
                stepped = false;
                continue;
            }
            }
            error = "unknown preparation phase";
            return false;
        }
    };

    // A continued preparation was saved with its next step due.
    for (bool step_due = continuing || until_next_step(false); step_due; step_due = until_next_step(true))
        if (std::string e = step_once(); !e.empty()) return Err(e);
    if (!error.empty()) return Err(error);

    PreparationReport report;
    report.top_plate_wall = st.top_plate_wall;
    report.settled = st.settled_before_lid && st.settled_under_lid;
    // The grains as grains (grain_volumes): a clump is one, of the volume
    // of the union of its spheres and its volume-equivalent radius (the size
    // it was drawn with); its spheres overlap, so their volumes would count
    // the overlaps twice.
    const GrainVolumes grains = grain_volumes(w);
    const std::vector<double>& grain_radii = grains.radius_m;
    const double grain_volume = grains.total_volume_m3;
    report.grains = grain_radii.size();
    report.wire_nodes = w.of(BodyKind::wire).size();
    report.wire_length_m = wire_length_m(w);
    report.nozzle_path_m = with_wire ? nozzle.path_m() : 0.0;
    report.pile_height_m = w.walls[report.top_plate_wall].point_m.z();
    report.sample_volume_m3 = std::numbers::pi * R * R * report.pile_height_m;
    report.grain_volume_fraction = grain_volume / report.sample_volume_m3;
    report.wire_volume_fraction = std::numbers::pi * spec.wire.radius_m * spec.wire.radius_m
                                * report.wire_length_m / report.sample_volume_m3;
    // The core: a grain diameter inside the membrane's inner surface and the
    // plates (core_sampling).
    const CoreSampling sampling = core_sampling(r_max, spec.grain_radius_m, spec.grain_sizes);
    const CoreFractions core = core_volume_fractions(w, R - r_m, 0.0, report.pile_height_m, sampling.margin_m, sampling.grid_m);
    report.core_grain_volume_fraction = core.grain;
    report.core_wire_volume_fraction = core.wire;
    if (spec.grain_sizes && !grain_radii.empty()) report.grain_sizes = grain_size_report(grain_radii, *spec.grain_sizes);
    report.simulated_time_s = w.time_s;
    report.steps = st.steps;
    report.time_step_s = dt;
    report.wall_time_s = st.wall_time_s + std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return report;
}

double smallest_grain_radius_m(const PreparationSpec& spec)
{
    if (spec.grain_sizes) return 0.5 * spec.grain_sizes->diameters_m.front();
    return spec.grain_radius_m * (1.0 - spec.grain_radius_spread);
}

void add_smallest_grain(World& w, const PreparationSpec& spec, std::uint8_t material)
{
    if (spec.grain_shape) // a clump of the smallest size: its smallest sphere, the mass its contacts see
        add_clump(w, scaled_clump(*spec.grain_shape, smallest_grain_radius_m(spec)), Vec3(0, 0, 1), Quat::Identity(),
            material);
    else
        add_grain(w, Vec3(0, 0, 1), smallest_grain_radius_m(spec), material);
}

StabilityInputs::Kind smallest_grain_stability(const PreparationSpec& spec)
{
    World probe;
    Material grain = spec.grain;
    grain.density_kg_per_m3 *= spec.density_scale; // as empty_column scales it
    add_smallest_grain(probe, spec, add_material(probe, grain));
    return stability_inputs(probe).kinds[static_cast<std::size_t>(BodyKind::grain)];
}

double largest_grain_radius_m(const PreparationSpec& spec)
{
    return largest_grain_radius_m(spec.grain_radius_m, spec.grain_radius_spread, spec.grain_sizes, spec.grain_shape);
}

double required_membrane_height_m(const PreparationSpec& spec)
{
    const double r_max = largest_grain_radius_m(spec);
    return estimated_fill_height_m(spec) + 8.0 * r_max;
}

double wire_reach_limit_m(const PreparationSpec& spec)
{
    return spec.membrane_radius_m - spec.membrane.contact_radius_m - spec.wire.radius_m - spec.clearance_m;
}

double wire_cover_height_m(const PreparationSpec& spec)
{
    return spec.wire_cover_m.value_or(2.0 * largest_grain_radius_m(spec));
}

double estimated_fill_height_m(const PreparationSpec& spec)
{
    // Radii uniform in r (1 ± s): E[r³] = r³ (1 + s²); from a curve,
    // E[r³] = E[D³]/8. (Two products: the spread's keeps its operations.)
    const double grains_4pi_3 = static_cast<double>(spec.grain_count) * 4.0 / 3.0 * std::numbers::pi; // N · 4π/3
    const double grain_volume_m3 = spec.grain_sizes
        ? grains_4pi_3 * (GrainSizeDistribution(*spec.grain_sizes).mean_cubed_diameter_m3() / 8.0)
        : grains_4pi_3 * std::pow(spec.grain_radius_m, 3) * (1.0 + spec.grain_radius_spread * spec.grain_radius_spread);
    return grain_volume_m3 / (assumed_packing_fraction * std::numbers::pi * spec.membrane_radius_m * spec.membrane_radius_m);
}

double wire_laying_height_m(const PreparationSpec& spec)
{
    return estimated_fill_height_m(spec) - wire_cover_height_m(spec);
}

double estimated_wire_length_m(const PreparationSpec& spec)
{
    const double laying_m = wire_laying_height_m(spec);
    if (spec.pattern.pattern == PatternKind::none || !(laying_m > 0.0)) return 0.0;
    const double pour_time_s = laying_m / spec.fill_rate_m_per_s;
    return spec.pattern.angular_speed_rad_per_s * spec.pattern.helix_radius_m * pour_time_s;
}

double fill_rate_for_wire_length_m_per_s(const PreparationSpec& spec, double wire_length_m)
{
    if (spec.pattern.pattern == PatternKind::none) return 0.0;
    return spec.pattern.angular_speed_rad_per_s * spec.pattern.helix_radius_m * std::max(0.0, wire_laying_height_m(spec))
         / wire_length_m;
}

} // namespace wiredem::engine
