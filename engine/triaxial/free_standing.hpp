// The free-standing test (issue 39) on a prepared World: the column is taken
// out of its formwork and loaded with nothing around it, as a printed column
// stands in a building. A sequence of the phases the triaxial test shares
// (formwork.hpp, loading.hpp, sampling.hpp):
//
//   1. removal   the formwork goes without a kick: the rigid membrane's radius
//                opens at a constant speed by removal_distance_m over
//                removal_time_s while the top plate rises as far, then the
//                membrane no longer touches anything;
//   2. settling  the column settles on the bottom plate under its real weight
//                until it is at rest by the preparation's kinetic-energy
//                criterion (or max_settling_time_s): whether it stands (at
//                rest, its grains' bulk height kept and few grains lost), its
//                height loss, its radius against height, the grains that left
//                it (beyond escape_distance_m from the axis);
//   3. dead load (optional) the top plate is set on the column and pushes it
//                with a constant force (ramped in), held for a stated time:
//                does it hold, and how much does it creep;
//   4. loading   unconfined compression: the top plate moves down at a
//                constant speed until the column fails (its axial stress fell
//                to 1 − failure_drop of its largest) or the target strain;
//   or
//   4. pull_out  (optional, instead of the dead load and the compression)
//                one end of the wire is pulled out at a constant speed
//                (pull_out.hpp): the force it takes against the pulled
//                length, until a length, the pulled piece's exit from the
//                column or a time bound.
//
// Conventions as in sampling.hpp. The axial strain is measured from h₀, the
// height of the settled column (the top of its highest standing grain or
// wire node above the bottom plate, where the plate touches it); σ₁ = F_top / (π r₀²), the nominal
// stress on the settled column's cross-section (r₀ its equivalent radius,
// standing_column), as an unconfined compression test reports it. The
// unconfined compressive strength is the maximum of σ₁ smoothed over
// CurveTolerances::smoothing_strain, with the triaxial yield's peak /
// plateau / rising reading (analysis/strength.hpp). docs/model.md, "The
// free-standing test", derives every criterion.
//
// Deterministic for any thread count; a continued test ends bit-identically.
// Nothing throws across this API.
#pragma once

#include "analysis/strength.hpp"
#include "core/result.hpp"
#include "simulation.hpp"
#include "triaxial/free_standing_params.hpp"
#include "triaxial/pull_out.hpp"
#include "triaxial/sampling.hpp"
#include "triaxial/triaxial.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace wiredem::engine {

/// The phases of a free-standing test (the series' phase column).
enum class FreeStandingPhase : std::uint8_t { removal = 0, settling = 1, dead_load = 2, loading = 3, pull_out = 4 };

/// "removal", "settling", "dead_load", "loading", "pull_out".
[[nodiscard]] const char* to_string(FreeStandingPhase p) noexcept;

/// The quasi-static verdict of the compression reads the rows from the
/// first one at which σ₁ reached this fraction of its largest value on: the
/// toe before the plate bears on the column has no stress scale for the
/// inertial number.
inline constexpr double bearing_fraction = 0.1;

/// A constant force on the top plate, held for a time.
struct DeadLoad {
    double force_n = 0.0;                 ///< F [N], > 0
    /// The force rises over this time as ½(1 − cos(π t/T)) [s], ≥ 0.
    double ramp_time_s = 0.01;
    double hold_time_s = 0.05;            ///< F held this long after the ramp [s], > 0
};

/// Parameters of one free-standing test. All SI. Those a job gives as they
/// are (FreeStandingParams, free_standing_params.hpp), then the ones it
/// derives.
struct FreeStandingSettings : FreeStandingParams {
    /// A grain whose centre is farther than this from the axis has left the
    /// column [m], > 0.
    double escape_distance_m = 0.03;
    std::optional<DeadLoad> dead_load;    ///< none: no dead-load phase
    /// Axial strains of the compression at which to take snapshots (0 and the
    /// target are always added; clamped to [0, target]).
    std::vector<double> snapshot_strains{};
    /// As TriaxialSettings::real_weights: the test starts by giving every body its real weight.
    std::optional<TriaxialSettings::MassScaling> real_weights;
    /// Pull the wire out after settling instead of compressing the column
    /// (the plate_speed, target, failure and snapshot settings are then
    /// unused); not with a dead load. The top plate stays where the removal
    /// lifted it and rises with the pulled end (at v max(0, d̂_z)), so that
    /// it never touches the wire pulled up. The region "in the column" is
    /// the settled column: within escape_distance_m of the axis and at most
    /// h₀ above the bottom plate.
    std::optional<PullOutSettings> pull_out;
};

/// The rules the settings obey on their own, before any World is looked at
/// (SettingsError as for the triaxial test): run_free_standing checks them
/// first, and job validation asks the same function at the door.
[[nodiscard]] std::optional<SettingsError> free_standing_settings_error(const FreeStandingSettings& s);

/// The grains of a World as grains, not spheres (as grain_volumes counts
/// them): each free sphere at its centre with its radius, each clump at its
/// centre of mass with its volume-equivalent radius (3V/4π)^{1/3}; free
/// spheres first in id order, then the clumps in clump order. Without clumps
/// these are the grains' own positions and radii, in their order.
struct ColumnGrains {
    std::vector<Vec3> position_m;
    std::vector<double> radius_m;
};

/// The grains of `w` as grains.
[[nodiscard]] ColumnGrains column_grains(const World& w);

/// The height of the grains' bulk above a bottom plate at `bottom_m`: the
/// height H_b = z_q / q of a uniform column that has the share q
/// (`fraction`, in (0, 1]) of its grains' volume below the same height z_q.
/// V(z), the volume of the standing grains (within `escape_distance_m` of the
/// axis) below the plane z, counts each grain as the sphere of its radius
/// cut by the plane (a cap); z_q solves V(z_q) = q V(∞). A column whose grains
/// fill its cross-section evenly from the plate to H has V(z) = V z / H, so
/// H_b = H; grains (and wire, which is not counted) above the bulk that hold
/// less than 1 − q of the volume do not move it; a heap (a cone of height
/// H_c) reads H_c (1 − (1 − q)^{1/3})/q, 0.66 H_c at q = 0.95. 0 without a
/// standing grain [m].
[[nodiscard]] double bulk_height_m(const std::vector<Vec3>& position_m, const std::vector<double>& radius_m,
    double bottom_m, double escape_distance_m, double fraction);

/// The standing part of a column: the grains (and wire nodes) within the
/// escape distance of the axis. Grains are counted as grains (ColumnGrains:
/// a clump once, at its centre of mass).
struct StandingColumn {
    /// Highest top of a standing grain's sphere or wire node above the bottom
    /// plate: where a plate set on the column touches it [m].
    double top_m = 0.0;
    /// Highest top of any grain's sphere or wire node above the bottom plate,
    /// standing or not: where the top plate, a plane over the whole bottom
    /// plate, touches first [m]; above top_m when something that left the
    /// column lies higher (a ridge of the runout, a grain still falling).
    double highest_top_m = 0.0;
    /// The distance from the axis of that highest top's body [m].
    double highest_top_axis_distance_m = 0.0;
    /// The grains' bulk height (bulk_height_m at the given fraction) [m].
    double bulk_height_m = 0.0;
    /// Equivalent radius √(2⟨ρ²⟩) + ⟨r⟩ of the standing grains (ρ their
    /// centres' distance from the axis): the radius of a uniformly filled
    /// cylinder with the same second moment of its grain centres [m].
    double radius_m = 0.0;
    std::size_t grains = 0;          ///< grains of the column, standing or not
    std::size_t escaped_grains = 0;  ///< grains beyond the escape distance
    /// The escaped grains' share of all the grains' volume (each grain the
    /// sphere of its radius), in [0, 1].
    double lost_fraction = 0.0;
};

/// The standing column of `w` (bottom plate: wall 0), its bulk height at
/// `bulk_fraction`.
[[nodiscard]] StandingColumn standing_column(const World& w, double escape_distance_m, double bulk_fraction);

/// A radius profile: the equivalent radius (as StandingColumn's) of the
/// standing grains in horizontal slices of one mean grain diameter, from the
/// bottom plate up.
struct RadiusProfile {
    std::vector<double> height_m;  ///< slice centres above the bottom plate [m]
    std::vector<double> radius_m;  ///< equivalent radius of the slice [m]
    std::vector<std::uint32_t> grains;  ///< standing grains in the slice
};

/// The profile of grains at `position_m` with radii `radius_m` standing on a
/// bottom plate at `bottom_m` (slices without a grain are left out).
[[nodiscard]] RadiusProfile radius_profile(const std::vector<Vec3>& position_m, const std::vector<double>& radius_m,
    double bottom_m, double escape_distance_m);

/// The deposit of a column that collapsed, measured as the experiments on
/// axisymmetric granular collapse measure theirs (Lube et al., J. Fluid
/// Mech. 508, 2004; Lajeunesse et al., Phys. Fluids 16, 2004): its runout
/// radius r∞ and its final height H∞ (docs/validation.md, "Collapse of a
/// column without wire").
struct Deposit {
    /// r∞: the smallest radius about the axis that holds the outer edges
    /// (ρ + r) of `fraction` of the grains: the edge of the continuous
    /// deposit, without the few grains that rolled away from it [m].
    double runout_radius_m = 0.0;
    double max_radius_m = 0.0;  ///< the outermost grain edge from the axis [m]
    /// H∞: the top of the highest grain within r∞ of the axis above the bottom plate [m].
    double height_m = 0.0;
};

/// The deposit of grains at `position_m` with radii `radius_m` on a bottom
/// plate at `bottom_m`; `fraction` in (0, 1]. All zero without grains.
[[nodiscard]] Deposit deposit(const std::vector<Vec3>& position_m, const std::vector<double>& radius_m, double bottom_m,
    double fraction);

/// The vertical force the part of the system above the plane z = `z_m`
/// receives from the part below it through contacts and wire bonds (springs
/// and joints), > 0 pushing up [N]: every interaction with members on both
/// sides counts with its force on the members above (a body is above when
/// its centre is). Reads the forces of the last step; deterministic.
[[nodiscard]] double axial_force_through_plane_n(const World& w, double z_m);

/// The weight of the moving bodies of `w` as the World applies it: m g of
/// every dynamic body gravity acts on, and the vertical point loads (the
/// wire's real weight under mass scaling), > 0 downwards [N].
[[nodiscard]] double column_weight_n(const World& w);

/// What settling did to the column.
struct SettlingReading {
    bool at_rest = false;            ///< the kinetic-energy criterion was met
    double time_to_rest_s = 0.0;     ///< from the end of the removal [s] (the limit when not at rest)
    /// The standing column's top (StandingColumn::top_m: the highest grain
    /// or wire node) before the removal, and h₀ after settling, where the
    /// plate is set and the strain measured from [m]; and the change.
    double height_before_m = 0.0;
    double height_m = 0.0;
    double height_loss = 0.0;        ///< (before − after)/before
    /// The grains' bulk height H_b (bulk_height_m) before the removal and
    /// after settling [m], and its loss (before − after)/before, which the
    /// verdict reads.
    double bulk_height_before_m = 0.0;
    double bulk_height_m = 0.0;
    double bulk_height_loss = 0.0;
    double radius_before_m = 0.0;    ///< equivalent radius before the removal [m]
    double radius_m = 0.0;           ///< r₀ after settling [m]
    std::size_t grains = 0;          ///< the column's grains (a clump counts once)
    std::size_t escaped_grains = 0;  ///< grains beyond the escape distance
    double lost_fraction = 0.0;      ///< their share of the grains' volume
    /// The self-weight check: the column's weight (column_weight_n), and the
    /// bottom plate's force averaged over the last millisecond of settling,
    /// which equals it within base_force_tolerance_n, the largest change of
    /// the column's vertical momentum over that time divided by it,
    /// (√(2 M K₀) + √(2 M K₁))/τ (M the moving mass, K₀ and K₁ the kinetic
    /// energies at the two ends: |P| ≤ √(2 M K)) [N].
    double weight_n = 0.0;
    double base_force_n = 0.0;
    double base_force_tolerance_n = 0.0;
    /// At rest, bulk_height_loss ≤ max_height_loss and lost_fraction ≤
    /// max_lost_fraction (judge_settled_column).
    bool stands = false;
    double max_removal_kinetic_energy_j = 0.0; ///< largest kinetic energy during the removal [J]
    RadiusProfile profile_before;    ///< radius against height before the removal
    RadiusProfile profile;           ///< and after settling
};

/// Fills the settled column's part of `r` from `after` (the column after
/// settling): h₀, the bulk height, the radius, the grains lost, the losses
/// against the `before` fields r already holds (height_before_m,
/// bulk_height_before_m), and the verdict `stands` from r.at_rest and the
/// bounds of `s`.
void judge_settled_column(SettlingReading& r, const StandingColumn& after, const FreeStandingSettings& s);

/// The dead load's reading.
struct DeadLoadReading {
    double force_n = 0.0;             ///< F [N]
    double stress_pa = 0.0;           ///< F / (π r₀²) [Pa]
    double strain_at_load = 0.0;      ///< ε_a when the ramp ended
    double strain_at_end = 0.0;       ///< ε_a when the hold ended
    double creep_strain = 0.0;        ///< strain_at_end − strain_at_load
    /// The column carried F to the end of the hold: its strain stayed below
    /// the target strain throughout (a column that gives way runs the plate
    /// down to it; the piston's own oscillation on a stiff column is no
    /// failure, and the creep strain says how much it gave).
    bool holds = false;
};

/// How the unconfined compression failed, as far as the test's record shows
/// it (docs/model.md, "How it failed"): failure_mode's verdict.
enum class FailureMode : std::uint8_t {
    wire_break = 0,      ///< a wire segment broke within a row of the largest σ₁ (PeakFailure::wire)
    grains_spilling = 1, ///< more than max_lost_fraction of the grains' volume left the column in the compression
    bulging = 2,         ///< the column's widest slice widened by more than max_height_loss of r₀
    unresolved = 3,      ///< none of these: a failure inside the column's width (a shear band), or none
};

/// "wire_break", "grains_spilling", "bulging", "unresolved".
[[nodiscard]] const char* to_string(FailureMode m) noexcept;

/// What failure_mode reads of a compression.
struct FailureSigns {
    bool wire_broke_at_peak = false; ///< peak_failure at the largest raw σ₁ is PeakFailure::wire
    /// The grains' volume share that left the column (beyond the escape
    /// distance) during the compression: lost at its end − lost when settled.
    double spilled_fraction = 0.0;
    double bulge_m = 0.0;            ///< column_bulge_m from the settled profile to the one at the end [m]
    double radius_m = 0.0;           ///< r₀, the settled column's equivalent radius [m]
};

/// The verdict, in this order: wire_break when the wire broke at the peak;
/// grains_spilling when spilled_fraction > `max_lost_fraction` (the column,
/// standing before, would not stand by the grains it lost:
/// FreeStandingSettings::max_lost_fraction); bulging when bulge_m >
/// `max_radius_gain` × r₀ (widened by as much as `stands` allows a column
/// to shorten: FreeStandingSettings::max_height_loss); else unresolved.
[[nodiscard]] FailureMode failure_mode(const FailureSigns& s, double max_lost_fraction, double max_radius_gain) noexcept;

/// How much the widest slice of a column widened: the largest radius of
/// `after` minus the largest of `before` (RadiusProfile::radius_m); 0 when
/// either has no slice [m].
[[nodiscard]] double column_bulge_m(const RadiusProfile& before, const RadiusProfile& after) noexcept;

/// The unconfined compression's reading.
struct CompressionReading {
    /// The maximum of the smoothed σ₁ and its kind (peak / plateau /
    /// rising: a rising curve's value is a lower bound); its index is a row
    /// of the series.
    analysis::CurveReading strength;
    double strength_axial_strain = 0.0;       ///< ε_a there: the strain at failure
    double max_sigma1_pa = 0.0;               ///< the largest raw σ₁ [Pa] …
    std::size_t max_sigma1_sample = 0;        ///< … its row
    bool failed = false;                      ///< ended by failure_drop before the target
    RadiusProfile profile_at_peak;            ///< the bulge at the largest raw σ₁
    RadiusProfile profile_at_end;             ///< and at the end
    std::vector<double> wire_strain_at_peak;  ///< segment strain along the wire at the largest raw σ₁
    std::vector<double> wire_tension_at_peak_n; ///< E_w π r_w² × that strain [N]
    /// How it failed (failure_mode with the settings' bounds) and what that
    /// read; empty only in a record written before it was read (2026-12-06).
    std::optional<FailureMode> failure_mode;
    double spilled_fraction = 0.0;            ///< FailureSigns::spilled_fraction
    double bulge_m = 0.0;                     ///< FailureSigns::bulge_m [m]
};

/// Everything one free-standing test produced.
struct FreeStandingResult {
    TriaxialSeries series;                    ///< phase column: FreeStandingPhase values
    std::vector<TriaxialSnapshot> snapshots;  ///< compression snapshots in ascending strain
    std::optional<TriaxialSnapshot> peak_snapshot; ///< at the largest raw σ₁ (force network there)
    SettlingReading settling;
    std::optional<DeadLoadReading> dead_load;
    std::optional<CompressionReading> compression; ///< empty, with a warning, when the curve cannot be read (or with a pull-out)
    std::optional<PullOutReading> pull_out;   ///< with settings.pull_out: the pull, its rows those of the phase
    std::size_t loading_start_sample = 0;     ///< first row of the compression (or of the pull-out)
    QuasiStaticVerdict verdict;               ///< over the compression rows that bear load
    std::vector<std::string> warnings;
    /// The wire's segments that broke during the test, in order (none for an
    /// unbreakable wire).
    std::vector<TestWireBreak> wire_breaks;
    std::uint64_t steps = 0;
    double time_step_s = 0.0;
    double simulated_time_s = 0.0;
    double wall_time_s = 0.0;
};

/// The driver's own state between two steps (a checkpoint saves it with the World).
struct FreeStandingDriverState {
    std::uint64_t steps = 0;
    FreeStandingPhase phase = FreeStandingPhase::removal;
    std::uint64_t phase_start_step = 0;       ///< step at which the current phase began
    double reference_height_m = 0.0;          ///< h₀ for ε_a (the standing height until settled) [m]
    double reference_radius_m = 0.0;          ///< r₀ for σ₁ [m]
    std::uint64_t last_sample_step = std::numeric_limits<std::uint64_t>::max();
    std::size_t next_snapshot = 0;
    double max_sigma1_pa = 0.0;               ///< largest raw σ₁ of the compression so far
    RadiusProfile profile_at_max_sigma1;      ///< the radius profile there (of grains, not spheres)
    double max_window_sigma1_pa = 0.0;        ///< largest trailing-window mean σ₁ so far
    /// Strain since which that mean has been below the failure level (NaN: it is not).
    double below_since_strain = std::numeric_limits<double>::quiet_NaN();
    bool loading_begun = false;
    double window_force_n = 0.0;              ///< settling: bottom plate force summed over the window so far
    double window_kinetic_energy_j = 0.0;     ///< settling: kinetic energy as the window began [J]
    Vec3 pull_start_m = Vec3::Zero();         ///< pull-out: where the pulled node was when the pull began [m]
    double pull_force_sum_n = 0.0;            ///< pull-out: the pull force summed over the steps since the last row [N]
    double end_tension_sum_n = 0.0;           ///< and the end segment's tension along the pull [N]
    std::uint64_t pull_steps_summed = 0;      ///< the steps in those sums
    double wall_time_s = 0.0;
    /// The live springs' warning is in result.warnings (ColumnTestStepper
    /// reports it once per test, a continued test included).
    bool live_springs_reported = false;
    FreeStandingResult result;
};

/// How a host checkpoints a free-standing test and continues one (as TriaxialContinuation).
struct FreeStandingContinuation {
    std::function<void(const World&, const FreeStandingDriverState&)> between_steps;
    std::optional<FreeStandingDriverState> from;
};

/// The longest simulated time of a test (the removal, the longest settling,
/// the dead load and the compression to the target, or the pull-out's
/// max_time_s) on a column of height
/// `height_m` [s].
[[nodiscard]] double longest_free_standing_time_s(const FreeStandingSettings& s, double height_m);

/// Steps a test is expected to take: longest_free_standing_time_s at δt.
[[nodiscard]] std::uint64_t expected_free_standing_steps(const FreeStandingSettings& s, double height_m, double dt_s);

/// Runs one free-standing test on `sim.world` (grains, optional wire, the
/// rigid membrane of the preparation, bottom plate = wall 0, top plate =
/// `top_plate_wall`, δt set), leaving the World in its final state.
/// RunControl as run_triaxial's. Errors: settings out of range (naming the
/// field), walls missing, no grains, no membrane, δt above the stable step,
/// cancelled, blew up.
[[nodiscard]] Result<FreeStandingResult, std::string> run_free_standing(Simulation& sim, std::size_t top_plate_wall,
    const FreeStandingSettings& settings, const RunControl& control = {}, FreeStandingContinuation continuation = {});

} // namespace wiredem::engine
