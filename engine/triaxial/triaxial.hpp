// The triaxial compression test (the model spec §6) on a prepared World, a
// sequence of the phases every column test shares (triaxial/formwork.hpp,
// pressure.hpp, consolidation.hpp, loading.hpp, sampling.hpp): the membrane
// becomes the cell's deformable sheet, sealed to the top cap; the confining
// pressure σ₃ is ramped up and held while the top plate, like a cell's
// loading cap (a piston of the column's mass pushed by σ₃), settles where
// σ₁ = σ₃ (isotropic consolidation); then the top plate moves down at
// constant speed to the target axial strain. Every sample_interval_s a row of
// measurements is recorded; snapshots of the whole system are taken at chosen
// axial strains. Signs and references: sampling.hpp.
//
// Determinism: every sum is either a reduce_blocks over canonical order or a
// serial loop in id order, so results are bit-identical for any thread count.
// Nothing throws across this API.
#pragma once

#include "analysis/strength.hpp"
#include "analysis/stress.hpp"
#include "core/result.hpp"
#include "simulation.hpp"
#include "triaxial/consolidation.hpp"
#include "triaxial/triaxial_params.hpp"
#include "triaxial/sampling.hpp"

#include <algorithm>
#include <array>
#include <cmath>
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

/// Parameters of one triaxial test. All SI. Those a job gives as they are
/// (TriaxialParams, triaxial_params.hpp), then the test's own: its σ₃, its
/// plate speed and the masses' scaling.
struct TriaxialSettings : TriaxialParams {
    double confining_pressure_pa = 40e3;      ///< σ₃ applied on the membrane [Pa], > 0
    double plate_speed_m_per_s = 0.2e-3;      ///< top plate speed while loading [m/s], > 0
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

/// A setting that run_triaxial refuses: the field (TriaxialSettings's name)
/// and why, beginning with its value ("0 must be > 0").
struct SettingsError {
    std::string field;
    std::string message;
};

/// The rules the settings obey on their own, before any World is looked at:
/// run_triaxial checks them first, and job validation asks the same
/// function at the door, so that an accepted job's tests start.
[[nodiscard]] std::optional<SettingsError> settings_error(const TriaxialSettings& s);

/// settings_error as one message, "field: why" (every cell's drivers check
/// it first), or nothing.
[[nodiscard]] std::optional<std::string> validate_triaxial_settings(const TriaxialSettings& s);

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
    /// The wire's segments that broke during the test, in order (none for an
    /// unbreakable wire).
    std::vector<TestWireBreak> wire_breaks;
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
    /// The live springs' warning is in result.warnings (ColumnTestStepper
    /// reports it once per test, a continued test included).
    bool live_springs_reported = false;
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

/// The hold of a test's consolidation phase (consolidation.hpp), every
/// cell's (run_triaxial, run_cuboid_triaxial): `advance()` takes a step (an
/// error message stops the hold) until `pre_load_steps`, then on until the
/// column has consolidated, at most the ramp and longest_hold_s. Consolidated:
/// σ₁, the plate `top_plate_wall`'s force averaged over consolidation_window_s
/// on the column's area, within consolidated_mismatch of `target_pa()`, and
/// the plate slower than the loading speed. The window is st's, so a
/// continued test goes on with it.
template <class Advance, class Target>
[[nodiscard]] std::optional<std::string> hold_until_consolidated(const World& w, std::size_t top_plate_wall,
    const TriaxialSettings& settings, TriaxialDriverState& st, std::uint64_t pre_load_steps, Advance&& advance,
    Target&& target_pa)
{
    const double dt = w.dt_s;
    const auto max_pre_load_steps
        = static_cast<std::uint64_t>(std::ceil((settings.pressure_ramp_time_s + longest_hold_s(settings)) / dt));
    const auto window_steps = static_cast<std::uint64_t>(std::max(1.0, std::round(consolidation_window_s / dt)));
    const auto consolidated = [&] {
        const double s3 = target_pa();
        return st.window_sigma1_pa && std::abs(*st.window_sigma1_pa - s3) <= consolidated_mismatch * s3
            && std::abs(w.walls[top_plate_wall].velocity_m_per_s.z()) <= settings.plate_speed_m_per_s;
    };
    while (st.steps < pre_load_steps || (st.steps < max_pre_load_steps && !consolidated())) {
        if (auto e = advance()) return e;
        st.window_force_n += plate_compression_n(w, top_plate_wall);
        if (++st.window_filled == window_steps) {
            st.window_sigma1_pa
                = analysis::axial_stress_pa(st.window_force_n / static_cast<double>(window_steps), st.column_radius_m);
            st.window_force_n = 0.0;
            st.window_filled = 0;
        }
    }
    return std::nullopt;
}


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

/// The readings every cell takes once its loading has ended, from the rows
/// of result.series (loading from row `loading_start_sample` on, at height
/// h₀ = `h0_m` then): ε_v of every row against V₀ = π r₀² h₀, the raw peak
/// of q, the yield state (analysis::read_strength) and the quasi-static
/// verdict; what cannot be read, and a test that was not quasi-static, are
/// warnings naming the test by its σ₃ [Pa].
void read_loading(TriaxialResult& result, double confining_pressure_pa, std::size_t loading_start_sample, double h0_m);

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
