// The triaxial test driver; see triaxial.hpp.
#include "triaxial/triaxial.hpp"

#include "analysis/stress.hpp"
#include "forces/membrane_forces.hpp"
#include "specimen/packing.hpp"
#include "specimen/preparation.hpp"
#include "timestep.hpp"
#include "triaxial/formwork.hpp"
#include "triaxial/loading.hpp"
#include "triaxial/pressure.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>

namespace wiredem::engine {
namespace {

bool is_plate(const World& w, std::size_t wall, double normal_z)
{
    return wall < w.walls.size() && w.walls[wall].shape == Wall::Shape::plane
        && w.walls[wall].normal.isApprox(Vec3(0.0, 0.0, normal_z));
}

} // namespace

std::optional<std::string> validate_triaxial_settings(const TriaxialSettings& s)
{
    if (auto e = settings_error(s)) return e->field + ": " + e->message;
    return std::nullopt;
}

namespace {

std::optional<std::string> validate(const World& w, std::size_t top_plate_wall, const TriaxialSettings& s)
{
    if (auto e = validate_triaxial_settings(s)) return e;
    if (!is_plate(w, 0, 1.0)) return "wall 0 must be the bottom plate (a plane with its normal pointing up)";
    if (!is_plate(w, top_plate_wall, -1.0))
        return "wall " + std::to_string(top_plate_wall) + " must be the top plate (a plane with its normal pointing down)";
    if (w.of(BodyKind::grain).size() == 0) return "the world has no grains";
    if (w.of(BodyKind::membrane).size() == 0 || w.membrane.triangles.empty())
        return "the world has no membrane to apply the confining pressure on";
    if (!(w.dt_s > 0.0)) return "the time step is not set";
    const double h = w.walls[top_plate_wall].point_m.z() - w.walls[0].point_m.z();
    if (!(h > 0.0)) return "the top plate is not above the bottom plate";
    return std::nullopt;
}

} // namespace

std::optional<SettingsError> settings_error(const TriaxialSettings& s)
{
    auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
    auto non_negative = [](double v) { return std::isfinite(v) && v >= 0.0; };
    const auto error = [](const char* field, std::string message) {
        return std::optional<SettingsError>(SettingsError{field, std::move(message)});
    };
    if (!positive(s.confining_pressure_pa))
        return error("confining_pressure_pa", format_number(s.confining_pressure_pa) + " must be > 0");
    if (!(s.target_axial_strain > 0.0 && s.target_axial_strain < 1.0))
        return error("target_axial_strain", format_number(s.target_axial_strain) + " must lie in (0, 1)");
    if (!positive(s.plate_speed_m_per_s))
        return error("plate_speed_m_per_s", format_number(s.plate_speed_m_per_s) + " must be > 0");
    if (!non_negative(s.pressure_ramp_time_s))
        return error("pressure_ramp_time_s", format_number(s.pressure_ramp_time_s) + " must be ≥ 0");
    if (!non_negative(s.hold_time_s)) return error("hold_time_s", format_number(s.hold_time_s) + " must be ≥ 0");
    if (s.max_hold_time_s && !(std::isfinite(*s.max_hold_time_s) && *s.max_hold_time_s >= s.hold_time_s))
        return error("max_hold_time_s", format_number(*s.max_hold_time_s) + " is shorter than hold_time_s "
                                            + format_number(s.hold_time_s) + ": it must be at least that");
    if (!(s.pressure_ramp_time_s + s.hold_time_s > 0.0))
        return error("hold_time_s", format_number(s.hold_time_s) + " with pressure_ramp_time_s "
                                        + format_number(s.pressure_ramp_time_s)
                                        + ": their sum must be > 0, the column needs time under σ₃ before loading");
    if (!positive(s.sample_interval_s))
        return error("sample_interval_s", format_number(s.sample_interval_s) + " must be > 0");
    for (double e : s.snapshot_strains)
        if (!std::isfinite(e)) return error("snapshot_strains", "every strain must be finite");
    return std::nullopt;
}

std::pair<std::uint64_t, std::uint64_t> triaxial_progress(const TriaxialDriverState& st) noexcept
{
    const std::uint64_t total = std::max(st.expected_steps, st.steps);
    if (!st.loading || !(st.progress_at_loading > 0.0) || total <= st.loading_start_step) return {st.steps, total};
    const double along = static_cast<double>(st.steps - st.loading_start_step)
                       / static_cast<double>(total - st.loading_start_step);
    const double f = st.progress_at_loading + (1.0 - st.progress_at_loading) * std::min(1.0, along);
    return {std::min(total, static_cast<std::uint64_t>(f * static_cast<double>(total))), total};
}

double longest_hold_s(const TriaxialSettings& s)
{
    return s.max_hold_time_s.value_or(default_max_hold_factor * s.hold_time_s);
}

double loading_time_s(const TriaxialSettings& s, double height_m)
{
    return loading_time_s(s.target_axial_strain, height_m, s.plate_speed_m_per_s);
}

std::uint64_t expected_triaxial_steps(const TriaxialSettings& s, double height_m, double dt_s)
{
    // The longest hold: progress never passes 100 % while σ₃ is held longer
    // than hold_time_s; run_triaxial re-counts when the loading starts.
    const auto pre_load = static_cast<std::uint64_t>(std::ceil((s.pressure_ramp_time_s + longest_hold_s(s)) / dt_s));
    return pre_load + static_cast<std::uint64_t>(std::ceil(loading_time_s(s, height_m) / dt_s));
}

Result<TriaxialResult, std::string> run_triaxial(
    Simulation& sim, std::size_t top_plate_wall, const TriaxialSettings& settings, const RunControl& control)
{
    return run_triaxial(sim, top_plate_wall, settings, control, {});
}

void read_loading(TriaxialResult& result, double confining_pressure_pa, std::size_t loading_start_sample, double h0)
{
    // Volumetric strain of every row against V₀ at loading start.
    TriaxialSeries& ts = result.series;
    const double v0 = analysis::cylinder_volume_m3(ts.column_radius_m[loading_start_sample], h0);
    result.initial_volume_m3 = v0;
    ts.volumetric_strain = volumetric_strains(ts, v0);

    // Peak of q over the loading samples.
    const std::span<const double> q_loading(ts.deviatoric_stress_pa.data() + loading_start_sample, ts.size() - loading_start_sample);
    if (const auto peak = analysis::peak_deviatoric_stress(q_loading)) {
        const std::size_t i = loading_start_sample + peak->index;
        result.peak_sample = i;
        result.peak_deviatoric_stress_pa = peak->value_pa;
        result.peak_axial_strain = ts.axial_strain[i];
        result.peak_sigma1_pa = ts.sigma1_pa[i];
        result.peak_sigma3_effective_pa = ts.sigma3_effective_pa[i];
    } else {
        // (A named string: GCC 12 warns -Warray-bounds, wrongly, on the literal
        // pushed here once inlined.)
        static const std::string no_peak = "no valid deviatoric stress sample during loading: no peak";
        result.warnings.push_back(no_peak);
    }

    // The yield state and the shapes of the curves (analysis/strength.hpp).
    {
        const auto from = static_cast<std::ptrdiff_t>(loading_start_sample);
        const std::span<const double> strain(ts.axial_strain.begin() + from, ts.axial_strain.end());
        const std::span<const double> s1(ts.sigma1_pa.begin() + from, ts.sigma1_pa.end());
        const std::span<const double> s3(ts.sigma3_effective_pa.begin() + from, ts.sigma3_effective_pa.end());
        if (auto reading = analysis::read_strength(strain, s1, s3)) {
            result.strength = reading.value();
            result.strength->stress_ratio.index += loading_start_sample;
            result.strength->deviatoric.index += loading_start_sample;
        } else {
            result.warnings.push_back("test at σ₃ = " + format_number(confining_pressure_pa)
                                      + " Pa: no yield state: " + reading.error());
        }
    }

    QuasiStaticVerdict& v = result.verdict;
    v = quasi_static_verdict(ts, loading_start_sample);
    if (!v.quasi_static) {
        v.warning = "test at σ₃ = " + format_number(confining_pressure_pa) + " Pa was not quasi-static: " + v.warning
                  + "; lower the plate speed or the density scaling";
        result.warnings.push_back(v.warning);
    }
}

Result<TriaxialResult, std::string> run_triaxial(Simulation& sim, std::size_t top_plate_wall,
    const TriaxialSettings& settings, const RunControl& control, TriaxialContinuation continuation)
{
    const auto wall_start = std::chrono::steady_clock::now();
    World& w = sim.world;
    ThreadPool& pool = sim.pool();
    if (auto e = validate(w, top_plate_wall, settings)) return Err(*e);
    constexpr std::size_t bottom_plate_wall = 0;
    const TranslationalState& nodes = w.of(BodyKind::membrane);
    const auto plates_apart_m = [&] {
        return w.walls[top_plate_wall].point_m.z() - w.walls[bottom_plate_wall].point_m.z();
    };

    // Everything that changes from step to step outside the World; the
    // lambdas below read and write it only (a checkpoint saves it).
    const bool continued = continuation.from.has_value();
    TriaxialDriverState st = continued ? std::move(*continuation.from) : TriaxialDriverState{};
    TriaxialResult& result = st.result;
    if (!continued) {
        // Formwork: the membrane becomes the cell's, sealed to the cap.
        st.cap_nodes = seal_membrane_to_cap(w, top_plate_wall);
        if (settings.real_weights)
            set_weights(w, settings.real_weights->density_scale, settings.real_weights->wire_mass_scale, 1.0);
        w.membrane.pressure_pa = 0.0;
        w.walls[top_plate_wall].velocity_m_per_s.setZero();
        if (auto warning = sample_interval_warning(settings.sample_interval_s, w.dt_s))
            result.warnings.push_back("test at σ₃ = " + format_number(settings.confining_pressure_pa) + " Pa: " + *warning);
    } else if (std::any_of(st.cap_nodes.begin(), st.cap_nodes.end(), [&](std::uint32_t i) { return i >= nodes.size(); })
               || st.steps > std::numeric_limits<std::uint64_t>::max() / 2) {
        return Err(std::string("the test's saved state does not belong to this World (a cap node is not a membrane node)"));
    } else {
        // Kinematic already, unless the World comes from a snapshot of
        // version 2 (held by their inverse mass; engine/io/snapshot.cpp).
        for (std::uint32_t i : st.cap_nodes) set_motion(w, {BodyKind::membrane, i}, Motion::kinematic);
    }
    const double dt = w.dt_s;
    const StableStep crit = stable_time_step(w);
    if (dt > crit.critical_s)
        return Err("time step " + format_number(dt) + " s exceeds the stable limit " + format_number(crit.critical_s)
                   + " s set by the " + crit.limited_by + " of the deformable system");
    if (crit.overdamped()) return Err(overdamped_error(crit, w.contact.normal_damping_s));

    // Grain properties for the inertial number (mass-scaled density if scaled).
    // A clump counts once, at its volume-equivalent radius.
    const TranslationalState& grains = w.of(BodyKind::grain);
    const double grain_radius_m = mean_grain_radius_m(w);
    const double grain_density = w.materials[grains.material[0]].density_kg_per_m3;

    const double pre_load_s = settings.pressure_ramp_time_s + settings.hold_time_s;
    const auto pre_load_steps = static_cast<std::uint64_t>(std::ceil(pre_load_s / dt));
    const std::uint64_t sample_every = steps_per_sample(settings.sample_interval_s, dt);
    const std::vector<double> plan = snapshot_plan(settings.target_axial_strain, settings.snapshot_strains);
    if (continued
        && (st.next_snapshot > plan.size() || (st.loading && st.loading_start_sample >= result.series.size())
            || !(st.reference_height_m > 0.0) || !(st.column_radius_m > 0.0)))
        return Err(std::string("the test's saved state is inconsistent (snapshot plan, loading start or heights)"));
    // The breaks the World had before the test (a continued test has recorded the rest).
    if (result.wire_breaks.size() > w.wire_breaks.size())
        return Err(std::string("the test's saved state is inconsistent (more wire breaks than the World has)"));
    const std::size_t breaks_before_test = w.wire_breaks.size() - result.wire_breaks.size();
    if (!continued) {
        st.reference_height_m = plates_apart_m();
        st.expected_steps = expected_triaxial_steps(settings, st.reference_height_m, dt);
        result.time_step_s = dt;
    }

    auto sample = [&] {
        TriaxialSample s = measure_triaxial_sample(w, pool, top_plate_wall, bottom_plate_wall, st.reference_height_m);
        s.time_s = static_cast<double>(st.steps) * dt;
        s.phase = st.loading ? TriaxialPhase::loading
                             : (s.time_s < settings.pressure_ramp_time_s ? TriaxialPhase::ramp : TriaxialPhase::hold);
        s.confining_pressure_pa = w.membrane.pressure_pa;
        if (st.loading) {
            // ε̇ = v/h₀ (the model spec §4), with the applied σ₃.
            s.inertial_number = analysis::inertial_number(
                settings.plate_speed_m_per_s / st.reference_height_m, grain_radius_m, grain_density, s.confining_pressure_pa);
        }
        result.series.push_back(s);
        st.last_sample_step = st.steps;
    };
    auto snapshot_due = [&] {
        const double strain = analysis::axial_strain(st.reference_height_m, plates_apart_m());
        take_due_snapshots(w, plan, st.next_snapshot, strain, static_cast<double>(st.steps) * dt, result.snapshots);
        return strain;
    };
    // Consolidation: while σ₃ ramps and holds, the top plate is the cell's
    // loading cap, a piston that the cell pressure pushes onto the column
    // with σ₃ π r² (r from the latest sample). It moves as a free body of the
    // column's mass under that force and the column's reaction: a passive
    // mechanical system, damped by the contacts, which comes to rest where
    // σ₁ = σ₃. Loading then starts from an isotropic state (q ≈ 0).
    if (!continued)
        st.column_radius_m
            = measure_triaxial_sample(w, pool, top_plate_wall, bottom_plate_wall, st.reference_height_m).column_radius_m;
    // A quasi-static consolidation needs no faster motion than the loading;
    // the cap at a few times that keeps a column that is still settling from
    // throwing the piston.
    const double max_piston_speed = max_piston_speed_factor * settings.plate_speed_m_per_s;
    double piston_mass_kg = 0.0;
    for (double m : grains.mass_kg) piston_mass_kg += m;
    // What σ₁ is brought to: the applied σ₃, or the column's own lateral
    // stress σ₃,eff averaged over the rows of the last consolidation window
    // (rows are the only place it is measured; a continued test has the
    // same rows, so the same targets).
    // A column the membrane does not touch has no σ₃,eff (zero): it is
    // brought to the applied σ₃ instead, and the result says so.
    auto effective_sigma3_pa = [&]() -> std::optional<double> {
        if (result.series.size() == 0) return std::nullopt;
        const TriaxialSeries& rows = result.series;
        const double s3_eff = consolidation_window_mean(rows, rows.sigma3_effective_pa, rows.size() - 1);
        if (std::isfinite(s3_eff) && s3_eff > 0.0) return s3_eff;
        return std::nullopt;
    };
    auto consolidation_target_pa = [&] {
        if (settings.consolidation == Consolidation::effective)
            if (const std::optional<double> s3_eff = effective_sigma3_pa()) return *s3_eff;
        return w.membrane.pressure_pa;
    };
    auto follow_the_pressure = [&] {
        const double target_n = consolidation_target_pa() * std::numbers::pi * st.column_radius_m * st.column_radius_m;
        double& v = w.walls[top_plate_wall].velocity_m_per_s.z();
        v = piston_velocity_m_per_s(v, target_n, plate_compression_n(w, top_plate_wall), dt, piston_mass_kg, max_piston_speed);
    };
    // One step (loading.hpp): σ₃ for the time reached (pressure), the plate
    // following it until loading (consolidation), the cap nodes carried with
    // the plate (formwork); then a row every sample_every steps (sampling).
    ColumnTestStepper<TriaxialDriverState> stepper(
        sim, control, continuation.between_steps, st, "the triaxial test", wall_start);
    auto advance = [&]() -> std::optional<std::string> {
        auto prescribe = [&] {
            const std::uint64_t n = st.steps;
            w.membrane.pressure_pa = ramped_pressure_pa(
                settings.confining_pressure_pa, static_cast<double>(n + 1) * dt, settings.pressure_ramp_time_s);
            if (!st.loading) follow_the_pressure();
            carry_with_cap(w, st.cap_nodes, top_plate_wall);
        };
        if (auto e = stepper.step(prescribe, [&] { return triaxial_progress(st); })) return e;
        if (w.wire_breaks.size() > breaks_before_test + result.wire_breaks.size())
            record_wire_breaks(w, breaks_before_test, static_cast<double>(st.steps) * dt,
                analysis::axial_strain(st.reference_height_m, plates_apart_m()), result.wire_breaks);
        if ((st.steps - 1) % sample_every == 0) {
            sample();
            st.column_radius_m = result.series.column_radius_m.back();
        }
        return std::nullopt;
    };

    // 1. Ramp and hold, the plate following the pressure, for at least
    // hold_time_s and then until the column has consolidated: σ₁ averaged
    // over a window within consolidated_mismatch of σ₃ and the plate slower
    // than the loading speed (a column still creeping under σ₃ keeps the
    // piston moving, and the piston's inertia keeps σ₁ off σ₃ while it
    // does). At most max_hold_time_s.
    if (!st.loading) {
        if (auto e = hold_until_consolidated(w, top_plate_wall, settings, st, pre_load_steps, advance, consolidation_target_pa))
            return Err(*e);
        result.hold_time_s = static_cast<double>(st.steps) * dt - settings.pressure_ramp_time_s;

        // 2. Loading at constant plate speed, from h₀ now.
        st.reference_height_m = plates_apart_m();
        result.initial_height_m = st.reference_height_m;
        st.loading = true;
        // The hold's length is known now: the steps left are the loading's
        // (progress jumps forward when the column consolidated early; when
        // the column is taller than it was at the start, the loading is
        // longer than first estimated, and progress goes on from where it
        // was instead of falling back: triaxial_progress).
        const std::uint64_t estimate_before = st.expected_steps;
        st.expected_steps
            = st.steps + static_cast<std::uint64_t>(std::ceil(loading_time_s(settings, st.reference_height_m) / dt));
        st.loading_start_step = st.steps;
        const std::uint64_t shorter = std::min(estimate_before, st.expected_steps);
        st.progress_at_loading = shorter > 0 ? std::min(1.0, static_cast<double>(st.steps) / static_cast<double>(shorter)) : 0.0;
        if (st.last_sample_step == st.steps) { // the grid sample of this step belongs to the loading
            result.series.phase.back() = static_cast<std::uint8_t>(TriaxialPhase::loading);
            result.series.axial_strain.back() = 0.0;
            result.series.inertial_number.back() = analysis::inertial_number(settings.plate_speed_m_per_s
                    / st.reference_height_m, grain_radius_m, grain_density, w.membrane.pressure_pa);
        } else {
            sample();
        }
        st.loading_start_sample = result.series.size() - 1;
        // The target over the rows loading_start reads: those of the window
        // ending at the loading's first row.
        const double target_pa = consolidation_target_pa();
        const bool to_effective = settings.consolidation == Consolidation::effective && effective_sigma3_pa();
        if (settings.consolidation == Consolidation::effective && !to_effective)
            result.warnings.push_back("test at σ₃ = " + format_number(settings.confining_pressure_pa)
                                      + " Pa: consolidation \"effective\" found no lateral stress σ₃,eff on the"
                                        " membrane (the column does not touch it), so the column was consolidated"
                                        " to the cell pressure σ₃ instead");
        result.consolidated_sigma1_pa = st.window_sigma1_pa.value_or(result.series.sigma1_pa[st.loading_start_sample]);
        result.consolidation = settings.consolidation;
        result.consolidation_target_pa = target_pa;
        if (const double s1 = result.consolidated_sigma1_pa; !within_consolidation_mismatch(s1, target_pa))
            result.warnings.push_back("test at σ₃ = " + format_number(settings.confining_pressure_pa)
                                      + " Pa had not consolidated when loading started: σ₁ = " + format_number(s1)
                                      + " Pa (mean over the last " + format_number(consolidation_window_s * 1e3)
                                      + " ms), more than " + format_number(100 * max_consolidation_mismatch) + " % off "
                                      + (to_effective ? "σ₃,eff = " + format_number(target_pa) + " Pa"
                                                      : std::string("σ₃"))
                                      + " after a hold of " + format_number(result.hold_time_s)
                                      + " s; lengthen hold_time_s or max_hold_time_s");
        snapshot_due();
        w.walls[top_plate_wall].velocity_m_per_s = Vec3(0.0, 0.0, -settings.plate_speed_m_per_s);
    }
    const double h0 = st.reference_height_m;
    const std::size_t loading_start_sample = st.loading_start_sample;
    const auto end = load_to_target(w, control, settings.target_axial_strain, advance, snapshot_due, [](double) { return false; });
    if (!end.ok()) return Err(end.error());
    const bool stopped_early = end.value() == LoadingEnd::host;
    w.walls[top_plate_wall].velocity_m_per_s.setZero();
    if (st.last_sample_step != st.steps) sample(); // the end of the test is always a row

    read_loading(result, settings.confining_pressure_pa, loading_start_sample, h0);
    const TriaxialSeries& ts = result.series;
    if (stopped_early)
        result.warnings.push_back("stopped by the host at axial strain " + format_number(ts.axial_strain.back())
                                  + " before the target " + format_number(settings.target_axial_strain));

    result.steps = st.steps;
    result.simulated_time_s = static_cast<double>(st.steps) * dt;
    result.wall_time_s = stepper.wall_time_s();
    return std::move(result);
}

} // namespace wiredem::engine
