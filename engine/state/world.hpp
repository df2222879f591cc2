// Everything a simulation step reads and writes, in three parts:
//   Model  — the definition a step reads and never writes: materials, the
//            contact law, gravity, which kinds touch, the wire's and the
//            membrane's models (parameters, mesh, rest lengths);
//   State  — what a step advances: the clock, the bodies and walls (each with
//            what defines it), the wire joints' rest angles;
//   Caches — what follows from Model and State and is rebuilt or rewritten:
//            the neighbour list (with the contacts' memory, which lives as
//            long as the listed contact), the cell grid, and every force a
//            step writes before it reads it.
// A World is all three (it derives from each), so a function can ask for the
// part it needs. state_hash covers the State and the contacts' memory; a
// snapshot saves everything needed to continue bit for bit (io/snapshot.hpp).
//
// Invariants: between steps, bodies change through the mutators below only
// (they drop what is derived from the bodies: the neighbour list, Gear-5's
// kept prediction; a direct write to a body's derivatives would be stepped
// from a stale prediction, which the sanitizer builds stop at); body ids
// follow creation order and never change; the scaled
// Gear derivatives are scaled by the current dt_s (set_time_step rescales
// them); how a body moves is its Motion (set_motion); Caches' per-body and
// per-wall arrays are sized with the bodies and walls (the add_… mutators).
#pragma once

#include "broadphase/cell_grid.hpp"
#include "contact/contact_list.hpp"
#include "core/types.hpp"
#include "laws/rolling.hpp"
#include "laws/tangential.hpp"
#include "state/body_state.hpp"
#include "state/clump_shape.hpp"
#include "state/clump_state.hpp"
#include "state/integrator.hpp"
#include "state/materials.hpp"
#include "state/membrane.hpp"
#include "state/point_loads.hpp"
#include "state/wire.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

namespace wiredem::engine {

/// The contact law shared by every pair (model spec §3).
struct ContactSettings {
    double normal_damping_s = 0.0;        ///< γ_n [s]
    TangentialParams tangential{};
    /// Rolling resistance between grains and of grains on walls (off by
    /// default: the model spec has none). laws/rolling.hpp.
    RollingParams rolling{};
};

/// A rigid, infinitely large wall: a plane (plate) or the inside of a
/// vertical cylinder. Walls have R = ∞ in the Hertz law. Its shape travels
/// with its pose (State::walls); what a step measures on it is
/// Caches::wall_loads.
struct Wall {
    enum class Shape : std::uint8_t { plane, cylinder };
    Shape shape = Shape::plane;
    Vec3 point_m = Vec3::Zero();          ///< plane: a point on it; cylinder: a point on the axis
    Vec3 normal = Vec3::UnitZ();          ///< plane: unit normal pointing into the domain
    double radius_m = 0.0;                ///< cylinder radius (axis ∥ z) [m]
    Vec3 velocity_m_per_s = Vec3::Zero(); ///< prescribed velocity; point_m moves with it
    std::uint8_t material = 0;
    /// The wall's own friction coefficient μ_w ≥ 0 in the tangential law of
    /// its contacts (0: frictionless, the tangential force is exactly zero);
    /// nullopt: the contact law's μ (ContactSettings::tangential), as every
    /// wall had before the rigid-wall cell (engine/triaxial/cuboid.hpp).
    /// The other tangential parameters and rolling resistance are the
    /// contact law's.
    std::optional<double> friction_coeff;
};

/// What the bodies exert on a wall in a step.
struct WallLoad {
    Vec3 total_force_n = Vec3::Zero();    ///< force the bodies exert on the wall this step [N]
    std::size_t contacts = 0;             ///< bodies touching the wall this step
};

/// A symmetric yes/no per pair of body kinds.
using KindMatrix = std::array<std::array<bool, body_kind_count>, body_kind_count>;

/// Which kinds touch by default. Membrane–membrane contact is not modelled
/// (model spec §3). Wire–membrane contact is, unlike the model spec says:
/// without it a laid coil, which springs outwards, passes through the
/// membrane (docs/model.md).
inline constexpr KindMatrix default_kinds_interact{{{true, true, true}, {true, true, true}, {true, true, false}}};

/// The definition of the system: what a step reads and never writes. Drivers
/// change it between steps, through the mutators where a change affects the
/// neighbour list (set_kinds_interact, …).
struct Model {
    /// Change it with set_integrator, which keeps the stored derivatives consistent.
    Integrator integrator = Integrator::gear5;
    MaterialTable materials;
    ContactSettings contact;
    /// Wire nodes fewer than this many apart along the chain never touch (model spec §3).
    std::uint32_t wire_contact_skip = 3;
    Vec3 gravity_m_per_s2{0.0, 0.0, -10.0};
    /// Whether gravity acts on a kind (never on membrane nodes: model spec §3).
    std::array<bool, body_kind_count> gravity_acts{true, true, false};
    /// Whether two kinds interact through contact (symmetric).
    KindMatrix kinds_interact = default_kinds_interact;
    /// External forces on single bodies (loads in tests, tip loads, the
    /// wire's weight under mass scaling), each added to its body's sum in the
    /// gather [N]. Sorted by body, each body at most once (state/point_loads.hpp).
    PointLoads point_loads;
    /// Verlet skin of the neighbour list [m]; ≤ 0 picks 0.2 × the largest radius.
    double skin_m = 0.0;
    WireChain wire;                       ///< the wire's parameters
    MembraneMesh membrane;                ///< the membrane's parameters, mesh and rest lengths
};

/// What a step advances.
struct State {
    double dt_s = 1e-7;
    double time_s = 0.0;
    std::uint64_t step_count = 0;
    std::array<TranslationalState, body_kind_count> bodies;  ///< by BodyKind
    RotationalState grain_rotation;       ///< parallel to bodies[grain]
    /// Rigid multi-sphere grains (state/clump_state.hpp); empty unless add_clump was called.
    ClumpState clumps;
    std::vector<Wall> walls;
    /// The rest angle ζ₀ ≥ 0 of the wire's joint at every node (0 at the two
    /// ends, which have no joint) [rad]. Starts at 0 (straight) when the node
    /// is appended and yields in compute_wire_forces; it travels with the
    /// specimen (copies of the World, result.h5's specimen group).
    std::vector<double> wire_rest_angle_rad;
    /// The segments removed from the wire (broken or cut), in the order it
    /// happened (state/wire.hpp). Empty for a whole wire.
    std::vector<WireBreak> wire_breaks;

    /// Total number of bodies over all kinds.
    [[nodiscard]] std::size_t body_count() const
    {
        return bodies[0].size() + bodies[1].size() + bodies[2].size();
    }
    /// Flat index of the first body of each kind, and the number of bodies.
    [[nodiscard]] FlatOffsets flat_offsets() const
    {
        FlatOffsets flat{};
        for (int k = 0; k < body_kind_count; ++k) flat[k + 1] = flat[k] + static_cast<std::uint32_t>(bodies[k].size());
        return flat;
    }
    /// Flat index of the first body of `kind` (grains, then wire, then membrane).
    [[nodiscard]] std::size_t flat_offset(BodyKind kind) const
    {
        std::size_t off = 0;
        for (int k = 0; k < static_cast<int>(kind); ++k) off += bodies[k].size();
        return off;
    }
    [[nodiscard]] TranslationalState& of(BodyKind k) { return bodies[static_cast<int>(k)]; }
    [[nodiscard]] const TranslationalState& of(BodyKind k) const { return bodies[static_cast<int>(k)]; }
};

/// x₀ and x₁ of every dynamic body (θ₁ of every dynamic grain) one
/// step ahead, as Gear-5's predictor would make them from the corrected
/// derivatives: the corrector, which holds those in registers, writes them,
/// and the next step takes them instead of reading the six derivative arrays
/// again (integrate/gear5.hpp). It holds for step `for_step` unless a mutator
/// has changed a body since (they set for_step to none). Not saved in a
/// snapshot: a restored run predicts afresh, with the same bits.
struct GearPrediction {
    static constexpr std::uint64_t none = std::numeric_limits<std::uint64_t>::max();
    std::array<std::array<std::vector<Vec3>, 2>, body_kind_count> x; ///< [kind][x₀, x₁]
    /// [unused, θ₁] of the grains (θ₀ is not integrated).
    std::array<std::vector<Vec3>, 2> theta;
    std::uint64_t for_step = none;                                   ///< the step count it was made for
};

/// What follows from Model and State: rebuilt when a body or wall has moved
/// half the skin or a mutator invalidated it (the neighbour list), or
/// rewritten by every step before it is read (the forces).
struct Caches {
    /// The contacts that may touch before the next rebuild. Their memory
    /// (tangential springs, touching flags) is state that lives as long as
    /// the listed contact: a rebuild carries it over (ContactList::rebuild),
    /// and state_hash covers it.
    ContactList contacts;
    NearPairs near;                        ///< the pairs of `contacts` that the kernel evaluates
    CellGrid grid;
    std::vector<Vec3> position_at_build_m; ///< flat positions at the last rebuild
    /// The skin the list was built with (effective_skin_m then) [m]: the list
    /// holds until something moves half of it, whatever skin_m says since.
    double skin_at_build_m = 0.0;
    /// Where each wall was at the last rebuild: it lists the bodies that may
    /// touch the wall before the next one (gap below r + skin), so the list is
    /// rebuilt as soon as the wall has moved half the skin.
    std::vector<Vec3> wall_point_at_build_m;
    bool neighbours_dirty = true;          ///< set by the mutators (add_…, set_motion, place_body, …), never by hand
    std::uint64_t neighbour_builds = 0;
    /// Gear-5's prediction of the next step, made by the last step's
    /// corrector (integrate/gear5.hpp). Every mutator of the bodies drops it.
    GearPrediction next_prediction;

    // Written by every step before anything reads them.
    std::array<std::vector<Vec3>, body_kind_count> body_force_n; ///< total force per body, by BodyKind [N]
    std::vector<Vec3> grain_torque_n_m;    ///< total torque per grain [N·m]
    ClumpLoads clump_loads;                ///< per clump (empty without clumps)
    std::vector<WallLoad> wall_loads;      ///< per wall
    WireForces wire_forces;
    MembraneForces membrane_forces;

    /// The force gathered on the bodies of a kind in the last step [N].
    [[nodiscard]] std::vector<Vec3>& force_of(BodyKind k) { return body_force_n[static_cast<int>(k)]; }
    [[nodiscard]] const std::vector<Vec3>& force_of(BodyKind k) const { return body_force_n[static_cast<int>(k)]; }
};

/// The whole simulated system. Functions that need one part take it (a World
/// is each of them); the mutators below take the World when a change in one
/// part invalidates another (a body added: the neighbour list and the force
/// slots).
struct World : Model, State, Caches {};

/// Adds a material; returns its id.
std::uint8_t add_material(World& w, const Material& m);

/// Adds a grain (solid sphere of the material's density) at rest or moving;
/// returns its index.
std::uint32_t add_grain(World& w, const Vec3& position_m, double radius_m, std::uint8_t material,
    const Vec3& velocity_m_per_s = Vec3::Zero(), const Vec3& angular_velocity_rad_per_s = Vec3::Zero());

/// Adds a clump: a rigid body of `body`'s spheres (its body frame:
/// state/clump_shape.hpp) of the material's density, its centre of mass at
/// `position_m`, turned by `orientation` (body → space), moving at
/// `velocity_m_per_s` and spinning at `angular_velocity_rad_per_s` (space
/// frame). Its spheres are appended as consecutive grains of
/// Motion::clumped and put in place. Returns the clump's index.
std::uint32_t add_clump(World& w, const ClumpBody& body, const Vec3& position_m, const Quat& orientation,
    std::uint8_t material, const Vec3& velocity_m_per_s = Vec3::Zero(),
    const Vec3& angular_velocity_rad_per_s = Vec3::Zero());

/// Puts clump `clump`'s spheres where it is, turned by `q` (its orientation,
/// or Gear-5's predicted one): x₀ = X + q b, x₁ = δt (V + ω × q b) and the
/// spin δt ω (space frame), ω = q ω_b, for each sphere's offset b. With
/// `arm_m` (indexed by grain id), each sphere's lever arm q b is written there.
void place_clump_spheres(State& s, std::uint32_t clump, const Quat& q, Vec3* arm_m = nullptr);

/// place_clump_spheres with the lever arms q b already worked out (`arm_m`,
/// indexed by grain id, as place_clump_spheres wrote them for the same q):
/// the same bits without turning each offset again.
void place_clump_spheres_at_arms(State& s, std::uint32_t clump, const Quat& q, const Vec3* arm_m);

/// The smallest mass a contact on a clump's sphere (grain `grain`) can see:
/// along a normal n through the sphere's centre, offset b from the clump's
/// centre, 1/m = 1/M + (b × n)ᵀ I⁻¹ (b × n) ≤ 1/M + |b|²/I₁, so
/// 1/(1/M + |b|²/I₁) [kg] (M for a sphere at the centre, as a lone grain's
/// mass; the stable time step's Hertz limit takes it).
[[nodiscard]] double clump_sphere_effective_mass_kg(const State& s, std::size_t grain);

/// Grains as bodies: free grains and clumps (a clump's spheres count once, as their clump).
[[nodiscard]] inline std::size_t grain_body_count(const State& s)
{
    const std::size_t spheres = s.of(BodyKind::grain).size();
    if (s.clumps.empty()) return spheres;
    std::size_t members = 0;
    for (const std::uint32_t n : s.clumps.member_count) members += n;
    return spheres - members + s.clumps.size();
}

/// Angular velocity of a clump in space [rad/s].
[[nodiscard]] Vec3 clump_angular_velocity_rad_per_s(const State& s, std::uint32_t clump);
/// Angular momentum of a clump about its centre of mass, space frame [kg·m²/s].
[[nodiscard]] Vec3 clump_angular_momentum(const State& s, std::uint32_t clump);

/// Adds a node of a kind without rotation (wire or membrane); returns its index.
std::uint32_t add_node(World& w, BodyKind kind, const Vec3& position_m, double radius_m, double mass_kg,
    std::uint8_t material, const Vec3& velocity_m_per_s = Vec3::Zero());

/// Adds a wall; returns its index.
std::size_t add_wall(World& w, Wall wall);
/// Removes a wall and its contacts; later walls' indices go down by one.
void remove_wall(World& w, std::size_t wall);
/// A horizontal plate at height z whose normal points up (+1, a floor) or down (−1, a lid).
[[nodiscard]] Wall make_plate(double z_m, double normal_sign, std::uint8_t material);
/// The inside of a vertical cylinder of radius r around the z axis.
[[nodiscard]] Wall make_cylinder(double radius_m, std::uint8_t material);

/// Changes δt, rescaling every stored Gear derivative (x[k] ∝ δt^k).
void set_time_step(World& w, double dt_s);

/// Switches the integrator. Both keep x₀, x₁ = δt v and x₂ = δt²/2 · a;
/// Gear-5's higher derivatives x₃…x₅ are zeroed, since Verlet does not keep them.
void set_integrator(World& w, Integrator integrator);

/// Velocity of a body [m/s] (from the scaled derivative x[1]).
[[nodiscard]] Vec3 velocity_m_per_s(const State& s, BodyRef b);
/// Angular velocity of a grain [rad/s].
[[nodiscard]] Vec3 angular_velocity_rad_per_s(const State& s, std::uint32_t grain);
/// Sets a body's velocity (a kinematic body's prescribed velocity).
void set_velocity(World& w, BodyRef b, const Vec3& v_m_per_s);
/// Sets how a body moves. A fixed body stops (x₁ … x₅ = 0); a kinematic one
/// keeps its velocity x₁, which set_velocity prescribes, and loses its
/// acceleration (x₂ … x₅ = 0); a dynamic one starts from its velocity. The
/// neighbour list is rebuilt (two bodies that are not dynamic need no contact).
void set_motion(World& w, BodyRef b, Motion motion);
/// Whether bodies of kinds a and b touch (both entries of the symmetric
/// matrix). The neighbour list is rebuilt at the next step.
void set_kinds_interact(World& w, BodyKind a, BodyKind b, bool interact);
/// Puts a body at a position, at rest: x₁ … x₅ = 0 (a grain stops turning
/// too). For set-ups and tests; the neighbour list is rebuilt at the next step.
void place_body(World& w, BodyRef b, const Vec3& position_m);
/// Scales every body's velocity and every grain's spin by `factor`: dynamic
/// relaxation towards a static state, in set-ups and tests (the model itself
/// has no global damping).
void scale_velocities(World& w, double factor);
/// Drops Gear-5's kept prediction: the next step predicts from the stored
/// derivatives. Every mutator of a body does this itself.
inline void invalidate_prediction(Caches& c) { c.next_prediction.for_step = GearPrediction::none; }
/// Drops the neighbour list: the next step rebuilds it. Every mutator above
/// does this itself; a caller never needs it but to force a rebuild.
void invalidate_neighbours(World& w);
/// Whether the integrator moves the body by its forces.
[[nodiscard]] inline bool is_dynamic(const TranslationalState& body, std::size_t i)
{
    return body.motion[i] == Motion::dynamic;
}
/// Whether the body moves by forces, its own or (a clump's sphere) its clump's:
/// such a body needs contacts, with walls too.
[[nodiscard]] inline bool moves_by_forces(const TranslationalState& body, std::size_t i)
{
    return body.motion[i] == Motion::dynamic || body.motion[i] == Motion::clumped;
}

} // namespace wiredem::engine
