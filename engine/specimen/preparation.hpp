// Specimen preparation, "rock printing" (the model spec §5): grains are poured
// into the rigid membrane on the bottom plate while a nozzle lays the wire
// along its pattern; then the packing settles and the top plate is lowered
// until it touches the pile.
//
// Deterministic: random numbers are drawn on the calling thread from the seed,
// and the engine step is thread-count independent.
#pragma once

#include "core/result.hpp"
#include "forces/membrane_forces.hpp"
#include "forces/wire_forces.hpp"
#include "simulation.hpp"
#include "specimen/grain_sizes.hpp"
#include "state/clump_shape.hpp"
#include "specimen/pattern.hpp"
#include "specimen/specimen_size.hpp"
#include "timestep.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace wiredem::engine {

/// What the preparation pours: the specimen's size as a job gives it
/// (SpecimenSize, specimen_size.hpp), then the rest.
struct PreparationSpec : SpecimenSize {
    /// When set, the grains' diameters are drawn from this curve instead
    /// (grain_radius_m and grain_radius_spread are then not used for sizes;
    /// smallest_grain_radius_m and the functions after it read either).
    std::optional<SieveCurve> grain_sizes;
    /// When set, every grain is a clump of this shape (state/clump_shape.hpp)
    /// in its body frame at a volume-equivalent radius of 1 m: a grain of
    /// radius r (drawn as without it) is this body × r, the volume of a
    /// sphere of radius r, poured turned to a uniformly random orientation.
    std::optional<ClumpBody> grain_shape;
    Material grain{};
    Material plate{1e9, 0.3, 7800.0};      ///< E_b
    WireSpec wire{};
    PatternSpec pattern{};
    MembraneSpec membrane{};               ///< radius/height/base are taken from above
    ContactSettings contact{};
    /// s: multiplies every mass (quasi-static scaling). Inertia only: the
    /// prepared specimen carries its real weight (see prepare_specimen).
    double density_scale = 1.0;
    /// M: extra inertia of the wire nodes (masses s·M times the model's),
    /// weights unchanged. The wire's springs then no longer set the time
    /// step; the membrane takes s only (docs/model.md, "Quasi-static scaling").
    double wire_mass_scale = 1.0;
    /// Speed at which the fill height rises while pouring [m/s]; sets the
    /// pouring time and therefore the length of wire laid: a helix's pitch
    /// is 2π v_fill / ω. At most max_fill_rate_per_rise_speed ×
    /// pattern.nozzle_rise_speed_m_per_s with a wire (the nozzle keeps up with the
    /// pile); the job field's default, 0.25 m/s, is half the paper's v_z^w.
    double fill_rate_m_per_s = 0.25;
    /// Grains enter the pouring zone moving down at this speed, or at 2.5 ×
    /// the fill rate if that is faster, so that the pour keeps to the fill
    /// rate (random placement fills the zone to only ~0.3) [m/s].
    double pour_speed_m_per_s = 0.5;
    /// Height of fill poured over the wire after the nozzle stops, so that
    /// its last turn is buried [m]; unset: one diameter of the largest grain.
    std::optional<double> wire_cover_m;
    double clearance_m = 1e-3;             ///< wire pattern keeps r_w + this inside the membrane
    double settle_kinetic_energy_per_grain_j = 1e-9;
    double max_time_s = 5.0;               ///< simulated time limit for the whole preparation
    double plate_speed_m_per_s = 0.05;     ///< the top plate's lowering speed
    double time_step_s = 0.0;              ///< 0: auto
    /// Integrator of the preparation; the prepared World keeps it, so the
    /// triaxial tests that start from it use it too.
    Integrator integrator = Integrator::gear5;
    std::uint64_t seed = 1;
};

struct PreparationReport {
    std::size_t grains = 0;
    std::size_t wire_nodes = 0;
    double wire_length_m = 0.0;
    /// Path the nozzle travelled while laying [m]: the wire it fed if it
    /// was never blocked. Much more than wire_length_m means it fell behind
    /// the pile and could not feed.
    double nozzle_path_m = 0.0;
    double pile_height_m = 0.0;            ///< bottom plate to top plate [m]
    double sample_volume_m3 = 0.0;         ///< π R² h
    double grain_volume_fraction = 0.0;
    double wire_volume_fraction = 0.0;     ///< wire as a cylinder of radius r_w along its length
    /// The same in the core of the column, a grain diameter away from the
    /// membrane's inner surface and both plates (core_volume_fractions).
    double core_grain_volume_fraction = 0.0;
    double core_wire_volume_fraction = 0.0;
    double simulated_time_s = 0.0;
    double wall_time_s = 0.0;
    std::uint64_t steps = 0;
    double time_step_s = 0.0;
    bool settled = false;                  ///< kinetic energy fell below the threshold in time
    std::size_t top_plate_wall = 0;        ///< index of the top plate in State::walls
    /// The drawn grains against the requested curve (only with one).
    std::optional<GrainSizeReport> grain_sizes;
};

/// The radius of the smallest grain the preparation can draw [m]: r (1 − s),
/// or half the curve's smallest diameter (a clump's volume-equivalent
/// radius). The stable time step takes it (a clump of that size with a
/// grain_shape).
[[nodiscard]] double smallest_grain_radius_m(const PreparationSpec& spec);

/// Adds to `w` one grain of the smallest size the preparation can draw, at
/// rest at (0, 0, 1) m, of material `material`: a sphere of
/// smallest_grain_radius_m, or, with a grain_shape, a clump of that
/// volume-equivalent radius (its smallest sphere, and the mass and inertia
/// its contacts see: stability_inputs of a World). What bounds the stable
/// time step among the grains (smallest_grain_stability).
void add_smallest_grain(World& w, const PreparationSpec& spec, std::uint8_t material);

/// The grains' part of the stable time step's inputs
/// (StabilityInputs::kinds[grain]): stability_inputs of a World holding one
/// add_smallest_grain of the grain material at its scaled density
/// (density_scale). The preparation's step and the job's estimate at the
/// door (api::stability_inputs) both come from it.
[[nodiscard]] StabilityInputs::Kind smallest_grain_stability(const PreparationSpec& spec);
/// The radius of the largest grain the preparation can draw [m]: r (1 + s),
/// or half the curve's largest diameter, times a clump's bounding radius
/// per volume-equivalent radius with a grain_shape. The pouring zone, the
/// column's width, the wire's cover and the cell grid take it.
[[nodiscard]] double largest_grain_radius_m(const PreparationSpec& spec);

/// Gravity on the scaled bodies: every body weighs `weight_factor` times its
/// real (unscaled) weight. Grains: Model::gravity_m_per_s2 = g · f / s; wire
/// nodes (masses s·M times real): gravity_acts is off for them and each
/// carries a point load f · m_real · g instead. Membrane nodes never weigh
/// anything (the model spec §3). Call again after adding wire nodes.
void set_weights(World& w, double density_scale, double wire_mass_scale, double weight_factor);

/// Kinetic energy of grains (translation and rotation) and wire nodes, the
/// nodes' masses divided by their extra scale M [J]: what the settling
/// criterion reads (settle_kinetic_energy_per_grain_j). Serial, in id order.
[[nodiscard]] double settling_energy_j(const World& w, double wire_mass_scale);

/// A settling energy and the grains it was summed over.
struct SettlingEnergy {
    double energy_j = 0.0;  ///< as settling_energy_j sums it [J]
    std::size_t grains = 0; ///< grains counted (a clump once, its spheres not)
};

/// settling_energy_j of the grains that `counts` keeps (asked with a free
/// sphere's centre, a clump's centre of mass) and of every wire node, and how
/// many grains that is. The free-standing test asks with its own "standing"
/// test, so its rest and its verdict read one definition of the column.
[[nodiscard]] SettlingEnergy settling_energy_of(
    const World& w, double wire_mass_scale, const std::function<bool(const Vec3& centre_m)>& counts);

/// The fill rate may be at most this times the nozzle's rise speed v_z^w when
/// a wire is laid. The nozzle follows the top of the pile under it, which
/// rises unevenly; at v_fill = v_z^w it fell behind and was blocked (a
/// paper-size column: 85 wire nodes laid of the 480 its path asked for), at
/// 0.5 v_z^w there (953 of 957) and at 0.6 v_z^w in the 300-grain test
/// columns it kept up.
inline constexpr double max_fill_rate_per_rise_speed = 0.6;

/// Standard gravity of the model (the model spec §3) [m/s²].
inline constexpr double standard_gravity_m_per_s2 = 10.0;

/// Stages reported to RunControl::progress are steps of the whole preparation
/// (expected total estimated from the pouring time).
///
/// Sequence. Grains are poured above the pile while the nozzle walks the
/// pattern, follows the top of the pile under it (at most v_z^w) and lays
/// each node on the pile, where nothing overlaps it, holding the wire's end.
/// Then the column settles, the mould goes, the top plate comes down until it
/// rests on the grains (pushing wire that stands out of the pile back in), the
/// nozzle lets go of the wire's end, the column settles again under the plate
/// and the plate follows it down to the grains.
///
/// Weights. The whole preparation runs with every weight scaled like the
/// masses (f = s): poured grains then fall, bounce and come to rest in real
/// time while δt grows as √s, and the packing, set by friction and the
/// pouring, does not depend on the weight scale while overlaps stay ≪ r_p.
/// The triaxial test gives every body its real weight (f = 1) when it starts.
///
/// Mould. While the membrane is rigid, a rigid cylinder on the inner surface
/// of the membrane's node spheres (radius R − r_m) keeps the wire in: a wire
/// laid along a curve springs outwards (it stores ½ k_rot ζ² per joint).
/// Meanwhile wire–membrane contact (docs/model.md) is off: a wire node pressed
/// into a hole of the rigid mesh against a mould is squeezed from four sides.
/// It is back on when the mould goes; a wire node at the mould then just
/// touches the node spheres, so in the triaxial test the deformable membrane
/// holds the wire without a jolt. The mould is removed before the top plate
/// comes down, so the prepared World has the bottom plate (wall 0) and the
/// top plate (top_plate_wall = 1) only.
/// @return the report, or an error message (pattern outside the membrane,
///         column taller than the membrane, cancelled, blew up)
[[nodiscard]] Result<PreparationReport, std::string> prepare_specimen(
    Simulation& sim, const PreparationSpec& spec, const RunControl& control = {});

/// The phases of a preparation, in order (see prepare_specimen).
enum class PreparationPhase : std::uint8_t {
    pouring,            ///< grains poured, the nozzle laying the wire
    settling,           ///< the column settles in the mould
    lowering_lid,       ///< the mould gone, the top plate comes down to the grains
    settling_under_lid, ///< the wire's end released, the column settles under the plate
    following_lid,      ///< the plate follows the column down to the grains
};

/// The preparation's own state between two steps: with the World, all it
/// needs to go on (a checkpoint saves both; prepare_specimen continues from
/// them). What is set up before the first step and never changes (the
/// materials, the mould's wall, δt) follows from the spec.
struct PreparationDriverState {
    PreparationPhase phase = PreparationPhase::pouring;
    std::uint64_t steps = 0;               ///< steps of the preparation so far
    std::uint64_t rng_state = 0;           ///< the pouring's SplitMix64 (starts at the seed)
    double owed_grains = 0.0;              ///< grains due but not yet placed
    double next_batch_s = 0.0;             ///< simulated time of the next batch [s]
    double poured_volume_m3 = 0.0;         ///< volume of the grains poured [m³]
    double pile_top_m = 0.0;               ///< top of the pile when last looked at [m]
    double nozzle_target_m = 0.0;          ///< height the nozzle moves towards [m]
    bool laid_all = false;                 ///< the nozzle has stopped laying and pays out
    /// The nozzle: its height, how far along its path it is and where along
    /// the path it laid the last node [m], and how far the path's own
    /// integration has come (NozzlePath::Integration: the spiral helix).
    struct NozzleState {
        double z_m = 0.0;
        double path_m = 0.0;
        double last_node_path_m = 0.0;
        NozzlePath::Integration path_integration;
    } nozzle;
    bool settled_before_lid = false;       ///< the first settling ended below the threshold (valid after it)
    bool settled_under_lid = false;        ///< the second did (valid after it)
    std::size_t top_plate_wall = 0;        ///< index of the top plate in State::walls (once added)
    double wall_time_s = 0.0;              ///< spent by the runs before this one [s]
};

/// How a host checkpoints a preparation and continues one.
struct PreparationContinuation {
    /// Called between every two steps of this run (not before its first, not
    /// after the last), also just before the run returns because it was
    /// cancelled, with the World and the driver's state: a consistent point
    /// to save both (io/snapshot.hpp). Saving changes nothing in the run.
    std::function<void(const World&, const PreparationDriverState&)> between_steps;
    /// When set, the preparation continues from this state instead of
    /// starting: sim.world must be the World saved with it, the spec the same.
    /// The report (but for its wall time) and the World at the end are
    /// bit-identical to those of a preparation that was never stopped.
    std::optional<PreparationDriverState> from;
};

/// prepare_specimen with checkpoints and continuation (see PreparationContinuation).
[[nodiscard]] Result<PreparationReport, std::string> prepare_specimen(Simulation& sim, const PreparationSpec& spec,
    const RunControl& control, PreparationContinuation continuation);

/// What prepare_specimen refuses before it starts, from the spec alone: a
/// pattern beyond wire_reach_limit_m, a fill rate that is not positive or
/// faster than the nozzle can follow, a membrane too short for the fill and
/// the pour. Job validation asks it of every accepted spec (its fuzz target
/// too), so that the answer at the door is the preparation's.
[[nodiscard]] std::optional<std::string> preparation_error(const PreparationSpec& spec);

/// How far from the axis the wire's pattern may reach, exclusive [m]: the
/// membrane's radius less its nodes' contact radius, the wire's radius and
/// the clearance, R − r_m − r_w − c (the model spec §5). prepare_specimen
/// refuses a pattern that reaches it; job validation says so before a job
/// is accepted, from this one rule.
[[nodiscard]] double wire_reach_limit_m(const PreparationSpec& spec);

/// Height the grains fill, estimated before pouring at a packing fraction of
/// 0.58 (prepare_specimen paces the pouring by it) from the mean grain volume
/// of the spread or of the curve [m].
[[nodiscard]] double estimated_fill_height_m(const PreparationSpec& spec);

/// Membrane height the preparation needs [m]: the estimated fill height and
/// room above it for the pouring zone (8 r_max). prepare_specimen refuses a
/// shorter membrane; job validation says so before a job is accepted.
[[nodiscard]] double required_membrane_height_m(const PreparationSpec& spec);

/// Height of fill poured over the wire after the nozzle has stopped [m]:
/// spec.wire_cover_m, or by default one diameter of the largest grain.
[[nodiscard]] double wire_cover_height_m(const PreparationSpec& spec);

/// Height of fill during which the nozzle lays wire, the estimated fill
/// height less the cover (wire_cover_height_m) [m]; ≤ 0 when the grains do not
/// rise above the cover, and then no wire can be laid: prepare_specimen
/// refuses a pattern then, and job validation says so before a job is
/// accepted, from this one figure.
[[nodiscard]] double wire_laying_height_m(const PreparationSpec& spec);

/// Length of wire prepare_specimen lays, estimated: ω R_a for the time the
/// fill takes to rise to the wire cover, (fill height − cover) / fill rate
/// [m]; 0 without a pattern or a fill over the cover.
[[nodiscard]] double estimated_wire_length_m(const PreparationSpec& spec);

/// The fill rate at which prepare_specimen lays `wire_length_m` of wire: the
/// inverse of estimated_wire_length_m, ω R_a (fill height − cover) / L
/// [m/s]; 0 without a pattern or a fill over the cover.
[[nodiscard]] double fill_rate_for_wire_length_m_per_s(const PreparationSpec& spec, double wire_length_m);

} // namespace wiredem::engine
