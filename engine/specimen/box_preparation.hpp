// Specimen preparation for the rigid-wall cuboid cell (issue 43;
// docs/model.md, "Preparing a specimen in the box"): the standard DEM
// triaxial preparation in a rigid-wall cell, as YADE's
// TriaxialStressController (its isotropic compaction stage) and PFC's servo
// walls do it. The grains are placed at random, without overlap, in a loose
// box (random sequential addition at a low packing fraction, drawn from the
// seed with the pour's SplitMix64); then the five moving walls of the cuboid
// cell (the top and the four lateral ones; the bottom is fixed) are servo
// walls driven to one consolidation stress σ_c, the cell's own servo
// (triaxial/cuboid.hpp: servo_wall_speed_m_per_s), until every wall holds
// σ_c within the tolerance and the grains are at rest (unbalanced force
// ratio below its bound). What sets the packing's density is the friction
// during the compaction, μ_c (YADE's "compactionFrictionDeg"): μ_c = 0 gives
// a dense packing near random close packing, the contact law's μ a looser
// one; after the compaction the contact law's μ is restored (a state at rest
// with |F_t| ≤ μ_c F_n stays admissible for every μ ≥ μ_c).
//
// No gravity during the compaction (an isotropic state; the weight of a
// 2 cm column of steel grains is ≈ 1.5 kPa, against σ_c of tens of kPa): the
// World comes out with g = 0, and the caller gives the grains their weight
// for the test if it wants it.
//
// Deterministic: the placement draws on the calling thread from the seed;
// the servo reads sums in contact order; the step is thread-count
// independent. Not checkpointed: the whole preparation is a pure function of
// the spec, so a host that was stopped during it prepares again and gets the
// same bits (BoxPreparation.SameBitsOnOneAndTwoThreads and
// .SameSeedSameBits).
#pragma once

#include "core/result.hpp"
#include "simulation.hpp"
#include "specimen/grain_sizes.hpp"
#include "specimen/preparation.hpp"
#include "triaxial/cuboid.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace wiredem::engine {

/// What a box preparation makes.
struct BoxPreparationSpec {
    std::size_t grain_count = 500;
    double grain_radius_m = 1.23e-3;
    double grain_radius_spread = 0.0;        ///< radii uniform in r (1 ± spread), as the pour's
    /// When set, the diameters are drawn from this curve instead (by number,
    /// as the pour draws them).
    std::optional<SieveCurve> grain_sizes;
    /// When set, every grain is this clump scaled to its drawn radius as its
    /// volume-equivalent radius (state/clump_shape.hpp), placed where its
    /// bounding sphere is free and turned at random, as the pour places them.
    std::optional<ClumpBody> grain_shape;
    Material grain{};
    Material wall{1e9, 0.3, 7800.0};         ///< the walls' material (the plates' E_b)
    ContactSettings contact{};               ///< the contact law; its μ is restored after the compaction
    /// Height of the loose box over its (square) width, h/L, in [0.25, 4]:
    /// 1 a cube, 2 the usual triaxial specimen's slenderness. The compaction
    /// is isotropic, so the prepared box keeps it to within the servo's play.
    double aspect_ratio = 1.0;
    /// The grains' volume fraction in the loose box they are placed in,
    /// (0, 0.35]: random sequential addition of equal spheres jams at ≈ 0.38.
    /// Counted over the part of the box the centres may take (the box less
    /// the largest radius at each wall), so a small box is as easy to fill;
    /// with a grain_shape, of the clumps' bounding spheres.
    double initial_packing_fraction = 0.25;
    double consolidation_pressure_pa = 20e3; ///< σ_c the walls compress to [Pa], > 0
    /// μ_c during the compaction (sets the density); nullopt: the contact law's μ.
    std::optional<double> compaction_friction_coeff;
    /// The walls' μ_w (cuboid.hpp: nullopt the contact law's, 0 frictionless).
    std::optional<double> wall_friction_coeff = 0.0;
    double servo_relaxation = default_servo_relaxation; ///< α ∈ (0, 1] of the servo
    /// Cap of a wall's speed [m/s]: a loose packing is compacted at most this
    /// fast (the walls touch nothing at first).
    double max_wall_speed_m_per_s = 0.05;
    /// At rest: every servo wall within this relative distance of σ_c ...
    double stress_tolerance = 0.01;
    /// ... and the unbalanced force ratio (mean |net force| on a grain over
    /// the mean contact force) below this, both at one check.
    double unbalanced_force_ratio = 0.01;
    double max_time_s = 1.0;                 ///< simulated time limit [s]
    double time_step_s = 0.0;                ///< 0: the auto step
    Integrator integrator = Integrator::gear5;
    std::uint64_t seed = 1;
};

/// What it made. The World: grains (ids in placement order), the six walls
/// (`walls`, add_cuboid_walls' order: bottom, top, x_min, x_max, y_min,
/// y_max), at rest, walls stopped, g = 0, δt set, the contact law's μ.
struct BoxPreparationReport {
    CuboidWalls walls;
    std::size_t grains = 0;
    CuboidStresses box;                      ///< the box and the walls' stresses at the end
    double sample_volume_m3 = 0.0;           ///< L_x L_y h
    double grain_volume_fraction = 0.0;      ///< Σ (4/3) π r³ / (L_x L_y h)
    /// The box's core, a largest grain's diameter inside all six walls,
    /// as the column's is measured (box_core_volume_fractions, core_sampling)
    double core_grain_volume_fraction = 0.0;
    double initial_volume_m3 = 0.0;          ///< of the loose box
    /// The loose box's fraction: the spec's, or lower where a grain found no
    /// place at it (each retry a fifth lower, down to 0.05).
    double initial_packing_fraction = 0.0;
    double unbalanced_force_ratio = 0.0;     ///< at the end
    double max_overlap_m = 0.0;              ///< the largest overlap of any contact at the end [m]
    bool at_rest = false;                    ///< the criteria held before max_time_s
    std::uint64_t steps = 0;
    double simulated_time_s = 0.0;
    double wall_time_s = 0.0;
    double time_step_s = 0.0;
    /// The drawn grains against the requested curve (only with one).
    std::optional<GrainSizeReport> grain_sizes;
};

/// What prepare_box_specimen refuses, from the spec alone: an error naming
/// the field, its value and the range.
[[nodiscard]] std::optional<std::string> box_preparation_error(const BoxPreparationSpec& spec);

/// The mean |net force| on the grains over the mean |force| of the touching
/// contacts after the last step (YADE's unbalancedForce); 0 with no contact.
/// A clump is one grain, its net force the sum on its spheres. Serial, in id
/// and contact order.
[[nodiscard]] double unbalanced_force_ratio(const World& w);

/// The box preparation of the grains a membrane preparation would pour, one
/// mapping for every host (a job's `specimen`, engine/specimen/
/// preparation.hpp): the count, the sizes (r and spread, or the curve), the
/// grain shape (clumps), the grain and plate materials (the grains' density × density_scale, the
/// pour's mass scaling), the contact law, the integrator, δt, the seed and the time limit;
/// σ_c and the walls' μ_w from the caller, the rest the box's defaults. The
/// wire, the membrane and the pour's rates have no meaning in a box.
/// @return the spec.
[[nodiscard]] Result<BoxPreparationSpec, std::string> box_preparation_from(
    const PreparationSpec& poured, double consolidation_pressure_pa, std::optional<double> wall_friction_coeff);

/// Builds the World in sim.world (replacing it) and compacts it (see the
/// file comment). RunControl: cancel every step, progress (steps done, an
/// estimate of the total).
/// @return the report, or an error: spec out of range, a grain that finds
///         no free place in the loose box, cancelled, blew up.
[[nodiscard]] Result<BoxPreparationReport, std::string> prepare_box_specimen(
    Simulation& sim, const BoxPreparationSpec& spec, const RunControl& control = {});

} // namespace wiredem::engine
