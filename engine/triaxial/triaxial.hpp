// The triaxial compression test (the model spec §6) on a prepared World:
// the membrane is made deformable, the confining pressure σ₃ is ramped up and
// held while the top plate, like a cell's loading cap (a piston of the
// column's mass pushed by σ₃), settles where σ₁ = σ₃ (isotropic
// consolidation), then the top plate moves down at constant speed
// to the target axial strain. Every sample_interval_s a row of
// measurements is recorded; snapshots of the whole system are taken at chosen
// axial strains.
//
// Conventions: forces on the plates and stresses are positive in compression;
// ε_a = (h₀ − h)/h₀ with h the distance between the plates and h₀ its value
// when loading starts; ε_v = (V₀ − V)/V₀ > 0 when the column contracts, with
// V = π r² h from the measured column radius r.
//
// Membrane above the top plate. A prepared membrane is usually taller than the
// column, and the plates are infinite planes: a free membrane node above the
// top plate would be pushed through it. As in a real cell, where the membrane
// is sealed to the top cap, every membrane node within its contact radius of
// the top plate or above it is clamped to the cap when the test starts: held
// (not integrated) and carried with the plate's velocity.
//
// Determinism: every sum is either a reduce_blocks over canonical order or a
// serial loop in id order, so results are bit-identical for any thread count.
// Nothing throws across this API.
#pragma once

#include "analysis/strength.hpp"
#include "core/result.hpp"
#include "simulation.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wiredem::engine {

/// Quasi-static thresholds (the model spec §4). A test is flagged as not
/// quasi-static when, during loading, the inertial number exceeds
/// `max_quasi_static_inertial_number` (I ≲ 10⁻³ is the usual quasi-static
/// regime, GDR MiDi 2004; above it the stress depends on the loading rate) or
/// the kinetic energy, averaged over the loading, exceeds
/// `max_quasi_static_energy_ratio` times the stored elastic energy (1 %: the
/// stored energy, not the motion, carries the load). The average, not the
/// largest sample: a slip event (q drops as a force chain buckles) turns
/// stored energy into motion at any plate speed, and a slower plate does not
/// make it smaller (measured on examples/main.json: the largest sample went
/// from 0.003 to 0.0105 when the plate slowed from 1 to 0.6 mm/s, at a drop
/// of q from 35.4 to 28.8 kPa; the mean stayed at 0.0015).
inline constexpr double max_quasi_static_inertial_number = 1e-3;
inline constexpr double max_quasi_static_energy_ratio = 1e-2;
/// Consolidation check: loading should start from an isotropic state. A test
/// warns when σ₁ (averaged over the last consolidation window) differs from
/// its consolidation target by more than this fraction when loading starts.
inline constexpr double max_consolidation_mismatch = 0.1;
/// Whether σ₁ [Pa] had consolidated to `target_pa` (within
/// max_consolidation_mismatch): the check behind the test's warning and its
/// `consolidated` verdict. False when either is not finite.
[[nodiscard]] bool within_consolidation_mismatch(double sigma1_pa, double target_pa) noexcept;
/// The hold goes on past hold_time_s (up to max_hold_time_s) until the column
/// has consolidated: σ₁, averaged over a window of this length, within
/// `consolidated_mismatch` of σ₃, and the top plate slower than the loading
/// speed. The window averages out single grain impacts on the plate (one
/// sample of σ₁ scatters by ±6 % at the paper's size, measured).
inline constexpr double consolidation_window_s = 5e-3;
inline constexpr double consolidated_mismatch = 0.05;
/// max_hold_time_s when not given: this many times hold_time_s.
inline constexpr double default_max_hold_factor = 4.0;
/// The top plate moves at most this many times the loading speed while it
/// consolidates the column.
inline constexpr double max_piston_speed_factor = 4.0;

/// What the top plate consolidates the column to while σ₃ ramps and holds
/// (docs/model.md, "Consolidation").
enum class Consolidation : std::uint8_t {
    /// σ₁ = σ₃: the cell pressure pushes the cap, as in a laboratory cell. A
    /// stiff membrane squeezes the column harder than that (σ₃,eff > σ₃), and
    /// a column it squeezes to its extension strength flows in extension
    /// while σ₃ is held.
    cell_pressure,
    /// σ₁ = σ₃,eff, the lateral stress the column feels (consolidation_window_mean):
    /// isotropic in the stresses the stress ratio is read from, so loading
    /// starts from η ≈ 0.
    effective,
};

/// "cell_pressure" or "effective".
[[nodiscard]] const char* to_string(Consolidation c) noexcept;
/// The inverse of to_string; nullopt for any other text.
[[nodiscard]] std::optional<Consolidation> consolidation_from_string(std::string_view text) noexcept;

/// Parameters of one triaxial test. All SI.
struct TriaxialSettings {
    double confining_pressure_pa = 40e3;      ///< σ₃ applied on the membrane [Pa], > 0
    double target_axial_strain = 0.10;        ///< loading stops when ε_a reaches this, in (0, 1)
    double plate_speed_m_per_s = 0.2e-3;      ///< top plate speed while loading [m/s], > 0
    /// σ₃ rises from 0 to the target over this time as ½(1 − cos(π t/T)), a
    /// ramp without a jump in rate at either end [s], ≥ 0 (0: a step).
    double pressure_ramp_time_s = 0.02;
    double hold_time_s = 0.02;                ///< σ₃ held (plate following σ₁ = σ₃) before loading [s], ≥ 0
    /// The hold lasts at least hold_time_s and goes on until the column has
    /// consolidated (see consolidated_mismatch), at most this long [s],
    /// ≥ hold_time_s; nullopt: default_max_hold_factor × hold_time_s.
    std::optional<double> max_hold_time_s;
    Consolidation consolidation = Consolidation::effective; ///< what σ₁ is brought to before loading
    double sample_interval_s = 1e-3;          ///< time between rows of the time series [s], > 0
    /// Axial strains at which to take snapshots; 0 (loading start) and the
    /// target are always added; values outside [0, target] are clamped.
    std::vector<double> snapshot_strains{};
    /// How the World's masses are scaled (engine/specimen/preparation.hpp).
    struct MassScaling {
        double density_scale = 1.0;     ///< s, every mass
        double wire_mass_scale = 1.0;   ///< M, wire nodes on top of s
    };
    /// When set, the test starts by giving every body its real weight
    /// (set_weights with factor 1: gravity g/s on the scaled masses): a
    /// prepared specimen carries weights scaled like its masses. The
    /// column unloads to its real weight while σ₃ ramps up.
    std::optional<MassScaling> real_weights;
};

/// The phase a sample was taken in.
enum class TriaxialPhase : std::uint8_t { ramp = 0, hold = 1, loading = 2 };

/// One row of measurements (see the file comment for signs and references).
struct TriaxialSample {
    double time_s = 0.0;                  ///< time since the test started [s]
    TriaxialPhase phase = TriaxialPhase::ramp;
    double axial_strain = 0.0;            ///< ε_a
    double height_m = 0.0;                ///< h, top plate z − bottom plate z [m]
    double top_plate_force_n = 0.0;       ///< vertical force the column exerts on the top plate [N]
    double bottom_plate_force_n = 0.0;    ///< same on the bottom plate [N]
    /// Mean radial distance of the grains touching the membrane + mean grain
    /// radius; without any grain–membrane contact, the radius of the smallest
    /// axis-centred cylinder that encloses the grains [m].
    double column_radius_m = 0.0;
    double confining_pressure_pa = 0.0;   ///< σ₃ applied on the membrane at this time [Pa]
    double sigma1_pa = 0.0;               ///< top plate force / (π r²) [Pa]
    double sigma3_effective_pa = 0.0;     ///< Σ grain– and wire–membrane |F_n| / (2π r h) [Pa]
    double deviatoric_stress_pa = 0.0;    ///< q = σ₁ − σ₃,eff [Pa]
    double stress_ratio = 0.0;            ///< (σ₁ − σ₃,eff)/(σ₁ + σ₃,eff)
    double volume_m3 = 0.0;               ///< π r² h [m³]
    double kinetic_energy_j = 0.0;        ///< translational + rotational, moving bodies [J]
    /// Hertz energy of the contacts that exert force (pairs, moving bodies on
    /// walls) + wire + membrane springs [J]
    double elastic_energy_j = 0.0;
    std::uint64_t contacts = 0;           ///< touching pairs + body–wall contacts
    std::uint64_t sliding_contacts = 0;   ///< of those, the ones not sticking
    std::uint64_t membrane_contacts = 0;  ///< touching grain– and wire–membrane pairs
    double wire_strain_mean = 0.0;        ///< mean segment strain (0 without wire)
    double wire_strain_max = 0.0;         ///< largest segment strain (0 without wire)
    /// I = ε̇ · 2 r_p · √(ρ_p/σ₃) with the applied σ₃; 0 while the plate is still.
    double inertial_number = 0.0;
};

/// The time series: one entry per sample in every vector, in time order.
struct TriaxialSeries {
    std::vector<double> time_s;
    std::vector<std::uint8_t> phase;               ///< TriaxialPhase values
    std::vector<double> axial_strain;
    std::vector<double> height_m;
    std::vector<double> top_plate_force_n;
    std::vector<double> bottom_plate_force_n;
    std::vector<double> column_radius_m;
    std::vector<double> confining_pressure_pa;     ///< applied σ₃
    std::vector<double> sigma1_pa;
    std::vector<double> sigma3_effective_pa;
    std::vector<double> deviatoric_stress_pa;
    std::vector<double> stress_ratio;
    /// ε_v relative to the volume at the start of loading (also for the
    /// samples before it, which then show the consolidation under σ₃).
    /// Derived from column_radius_m and height_m when the test ends
    /// (volumetric_strains); empty while it runs.
    std::vector<double> volumetric_strain;
    std::vector<double> kinetic_energy_j;
    std::vector<double> elastic_energy_j;
    std::vector<std::uint64_t> contacts;
    std::vector<std::uint64_t> sliding_contacts;
    std::vector<std::uint64_t> membrane_contacts;
    std::vector<double> wire_strain_mean;
    std::vector<double> wire_strain_max;
    std::vector<double> inertial_number;

    [[nodiscard]] std::size_t size() const { return time_s.size(); }
    /// Appends a row (every series but volumetric_strain).
    void push_back(const TriaxialSample& s);
};

/// ε_v = (V₀ − V)/V₀ of every row, V = π r² h from column_radius_m and height_m.
[[nodiscard]] std::vector<double> volumetric_strains(const TriaxialSeries& s, double initial_volume_m3);

/// Contacts of one instant: every touching body pair and every body–wall contact.
struct ForceNetwork {
    std::vector<BodyRef> first, second;   ///< body pairs, (kind, index), first < second
    std::vector<Vec3> force_n;            ///< force on `first` (−force on `second`) [N]
    std::vector<double> normal_force_n;   ///< |F_n| [N]
    std::vector<std::uint32_t> wall;      ///< body–wall contacts: wall index …
    std::vector<BodyRef> wall_body;       ///< … the body …
    std::vector<Vec3> wall_force_n;       ///< … and the wall's force on it [N]
};

/// The whole system at one instant.
struct TriaxialSnapshot {
    double requested_axial_strain = 0.0;  ///< the strain asked for
    double axial_strain = 0.0;            ///< the strain when taken (first step at or past it)
    double time_s = 0.0;                  ///< since the test started [s]
    std::vector<Vec3> grain_position_m;
    std::vector<double> grain_radius_m;
    std::vector<Vec3> grain_velocity_m_per_s;
    std::vector<Vec3> wire_node_position_m;
    std::vector<double> wire_segment_strain;
    std::vector<Vec3> membrane_node_position_m;
    std::vector<std::array<std::uint32_t, 3>> membrane_triangles; ///< node indices, (b−a)×(c−a) inwards
    ForceNetwork forces;
};

/// Whether the loading was slow enough to be called quasi-static.
struct QuasiStaticVerdict {
    bool quasi_static = true;
    double max_inertial_number = 0.0;     ///< over the loading samples
    double mean_kinetic_to_elastic = 0.0; ///< mean KE / elastic energy over the loading samples (the criterion)
    double max_kinetic_to_elastic = 0.0;  ///< its largest sample (slip events; not a criterion)
    std::string warning;                  ///< empty when quasi-static; otherwise what was exceeded
};

/// The quasi-static verdict over the rows from `loading_start` on (rows
/// evenly spaced in time): the largest inertial number, and the mean and
/// largest kinetic/elastic energy ratio (a row without elastic energy counts
/// as ∞). Flags the test when I or the mean ratio is above its threshold.
[[nodiscard]] QuasiStaticVerdict quasi_static_verdict(const TriaxialSeries& s, std::size_t loading_start);

/// The column as loading started, and what the ramp and hold did to it
/// (docs/model.md, "Consolidation"). A column whose membrane squeezes it
/// harder than the piston presses (σ₃,eff above σ₁) can yield in extension
/// while σ₃ is held: it lengthens after its shortest, and loading then
/// starts from η < 0 on a column that has just flowed the other way.
struct LoadingStart {
    std::size_t sample = 0;           ///< the series' first loading row
    /// σ₁ and σ₃,eff averaged over the rows of the last consolidation window
    /// (consolidation_window_s) up to that row, and η of those means.
    double sigma1_pa = 0.0;
    double sigma3_effective_pa = 0.0;
    double stress_ratio = 0.0;
    /// Axial strain of the ramp and hold, (h_first − h)/h_first from the
    /// first row to the loading row: > 0 shortened, < 0 lengthened.
    double axial_strain = 0.0;
    /// How much the column lengthened after its shortest before loading,
    /// (h − h_min)/h_first ≥ 0: the extension flow of the hold.
    double rebound_axial_strain = 0.0;
    /// Radial strain of the ramp and hold, (r_first − r)/r_first (> 0 narrowed).
    double radial_strain = 0.0;
};

/// The mean of `column` (a column of `s`) over the rows up to `last` within
/// consolidation_window_s of it: σ₁ and σ₃,eff as consolidation judges them.
[[nodiscard]] double consolidation_window_mean(const TriaxialSeries& s, const std::vector<double>& column, std::size_t last);

/// The loading start read from a series' rows (the phase column); nullopt
/// when the series has no loading row.
[[nodiscard]] std::optional<LoadingStart> loading_start(const TriaxialSeries& s);

/// The longest σ₃ is held before loading [s]: max_hold_time_s, or
/// default_max_hold_factor × hold_time_s.
[[nodiscard]] double longest_hold_s(const TriaxialSettings& s);

/// Simulated time of the loading to the target strain on a column of height
/// `height_m` at the plate speed [s].
[[nodiscard]] double loading_time_s(const TriaxialSettings& s, double height_m);

/// Steps a test is expected to take at time step `dt_s` on a column of
/// height `height_m`: the pressure ramp and the longest hold, then loading
/// to the target strain (run_triaxial reports progress against it, and
/// re-counts it when the loading starts).
[[nodiscard]] std::uint64_t expected_triaxial_steps(const TriaxialSettings& s, double height_m, double dt_s);

/// Everything one test produced.
struct TriaxialResult {
    TriaxialSeries series;
    std::vector<TriaxialSnapshot> snapshots;  ///< in ascending strain
    /// The raw maximum of q over the loading samples [Pa], and the state
    /// there. Not always a yield strength: a stiffening membrane can keep q
    /// rising to the end (see `strength` for its shape and the yield state).
    double peak_deviatoric_stress_pa = 0.0;
    double peak_axial_strain = 0.0;           ///< ε_a at that sample
    double peak_sigma1_pa = 0.0;              ///< σ₁ at that sample [Pa]
    double peak_sigma3_effective_pa = 0.0;    ///< σ₃,eff at that sample [Pa]
    std::size_t peak_sample = 0;              ///< index of that sample in the series
    /// The yield state (maximum of the stress ratio) and the shapes of the
    /// η and q curves (docs/model.md, "How yield is read"); empty, with a
    /// warning, when the loading curves cannot be read. Its sample indices
    /// are rows of `series`.
    std::optional<analysis::StrengthReading> strength;
    double initial_height_m = 0.0;            ///< h₀ [m]
    double initial_volume_m3 = 0.0;           ///< V₀ = π r₀² h₀ [m³]
    QuasiStaticVerdict verdict;
    std::vector<std::string> warnings;        ///< the verdict's warning and any other
    /// How long σ₃ was held before loading [s]: hold_time_s, or longer until
    /// the column had consolidated (at most max_hold_time_s).
    double hold_time_s = 0.0;
    /// σ₁ averaged over the last consolidation window before loading [Pa].
    double consolidated_sigma1_pa = 0.0;
    /// What σ₁ was brought to (the settings' consolidation) and the target as
    /// loading started [Pa]: σ₃, or σ₃,eff over the last window. The test
    /// consolidated when within_consolidation_mismatch(consolidated_sigma1_pa,
    /// consolidation_target_pa). Set when loading starts; empty and NaN in a
    /// test file written before they were recorded.
    std::optional<Consolidation> consolidation;
    double consolidation_target_pa = std::numeric_limits<double>::quiet_NaN();
    std::uint64_t steps = 0;
    double time_step_s = 0.0;
    double simulated_time_s = 0.0;            ///< ramp + hold + loading [s]
    double wall_time_s = 0.0;
};

/// The test driver's own state between two steps: with the World, all a test
/// needs to go on (a checkpoint saves both; run_triaxial continues from them).
/// The phases follow from it: ramp and hold while !loading, then loading.
struct TriaxialDriverState {
    std::uint64_t steps = 0;              ///< steps of this test so far
    std::uint64_t expected_steps = 0;     ///< the estimate progress is reported against
    bool loading = false;                 ///< the plate has started to move at the loading speed
    /// h₀ for ε_a: the height when the test started, then when loading started [m].
    double reference_height_m = 0.0;
    /// Step of the last row of the series (none yet: the largest value).
    std::uint64_t last_sample_step = std::numeric_limits<std::uint64_t>::max();
    std::size_t next_snapshot = 0;        ///< next entry of the snapshot plan
    std::size_t loading_start_sample = 0; ///< row where loading started (valid when loading)
    std::uint64_t loading_start_step = 0; ///< steps when loading started (valid when loading)
    /// The fraction of the test progress reported as loading started
    /// (triaxial_progress); 0: report steps against expected_steps as they are.
    double progress_at_loading = 0.0;
    /// Consolidation window: the plate force summed over its steps so far, …
    double window_force_n = 0.0;
    std::uint64_t window_filled = 0;      ///< … how many steps that is, …
    std::optional<double> window_sigma1_pa; ///< … and the last full window's mean σ₁ [Pa]
    double column_radius_m = 0.0;         ///< of the latest row [m]
    /// Membrane nodes clamped to the top cap (held, carried with the plate).
    std::vector<std::uint32_t> cap_nodes;
    double wall_time_s = 0.0;             ///< spent by the runs before this one [s]
    /// What has been measured: series and snapshots so far, hold time, h₀,
    /// consolidated σ₁ and warnings once loading has started.
    TriaxialResult result;
};

/// The progress of a test as (done, total): steps against expected_steps,
/// except during the loading when the loading turned out longer than the
/// estimate before it (a column taller than at the start): the fraction then
/// goes on from where it was as loading started (progress_at_loading) and
/// reaches 1 at the estimated end. Never decreases from one step to the next,
/// and is below 1 until the estimated end.
[[nodiscard]] std::pair<std::uint64_t, std::uint64_t> triaxial_progress(const TriaxialDriverState& st) noexcept;

/// Takes one row of measurements of `w` as it is after its last step (the
/// contact and wall forces of that step). time_s, phase, confining_pressure_pa
/// and inertial_number are left for the caller. Reads only; deterministic.
/// @param top_plate_wall    index of the top plate (a plane whose normal points down)
/// @param bottom_plate_wall index of the bottom plate (a plane whose normal points up)
/// @param initial_height_m  h₀ for ε_a [m], > 0
[[nodiscard]] TriaxialSample measure_triaxial_sample(const World& w, ThreadPool& pool, std::size_t top_plate_wall,
    std::size_t bottom_plate_wall, double initial_height_m);

/// Copies the system into a snapshot (forces of the last step).
[[nodiscard]] TriaxialSnapshot take_triaxial_snapshot(const World& w);

/// Runs one triaxial test on `sim.world` (grains, optional wire, membrane,
/// bottom plate = wall 0, top plate = `top_plate_wall`, δt set), leaving the
/// World in its final state. RunControl: `cancel` is checked every step,
/// `progress` receives (steps done, estimated total), `after_step` returning
/// false ends the loading early (the result then carries a warning).
/// @return the result, or an error: settings out of range, walls missing or
///         not plates, no membrane, δt above the critical step of the
///         deformable system, cancelled, blew up.
[[nodiscard]] Result<TriaxialResult, std::string> run_triaxial(Simulation& sim, std::size_t top_plate_wall,
    const TriaxialSettings& settings, const RunControl& control = {});

/// How a host checkpoints a test and continues one.
struct TriaxialContinuation {
    /// Called between every two steps of this run (not before its first, not
    /// after the last), also just before the run returns because it was
    /// cancelled, with the World and the driver's state: a consistent point
    /// to save both (io/snapshot.hpp). The host decides when to save; saving
    /// changes nothing in the run.
    std::function<void(const World&, const TriaxialDriverState&)> between_steps;
    /// When set, the test continues from this state instead of starting:
    /// sim.world must be the World saved with it. The result, and the World at
    /// the end, are bit-identical to those of a test that was never stopped.
    std::optional<TriaxialDriverState> from;
};

/// run_triaxial with checkpoints and continuation (see TriaxialContinuation).
[[nodiscard]] Result<TriaxialResult, std::string> run_triaxial(Simulation& sim, std::size_t top_plate_wall,
    const TriaxialSettings& settings, const RunControl& control, TriaxialContinuation continuation);

} // namespace wiredem::engine
