// The triaxial test driver; see triaxial.hpp.
#include "triaxial/triaxial.hpp"

#include "analysis/stress.hpp"
#include "energy.hpp"
#include "forces/membrane_forces.hpp"
#include "laws/hertz.hpp"
#include "specimen/preparation.hpp"
#include "timestep.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>

namespace wiredem::engine {
namespace {

/// Force the column exerts on plate `wall` along the plate's inward normal,
/// > 0 in compression (the wall's load is the force the bodies exert on it).
double plate_compression_n(const World& w, std::size_t wall)
{
    return -w.wall_loads[wall].total_force_n.dot(w.walls[wall].normal);
}

/// σ₃(t) during the ramp: ½(1 − cos(π t/T)) of the target, the target from T on.
double ramped_pressure_pa(double target_pa, double t_s, double ramp_s)
{
    if (t_s >= ramp_s) return target_pa;
    return target_pa * 0.5 * (1.0 - std::cos(std::numbers::pi * t_s / ramp_s));
}

std::string format_number(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

bool is_plate(const World& w, std::size_t wall, double normal_z)
{
    return wall < w.walls.size() && w.walls[wall].shape == Wall::Shape::plane
        && w.walls[wall].normal.isApprox(Vec3(0.0, 0.0, normal_z));
}

std::optional<std::string> validate(const World& w, std::size_t top_plate_wall, const TriaxialSettings& s)
{
    auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
    auto non_negative = [](double v) { return std::isfinite(v) && v >= 0.0; };
    if (!positive(s.confining_pressure_pa))
        return "confining_pressure_pa: " + format_number(s.confining_pressure_pa) + " must be > 0";
    if (!(s.target_axial_strain > 0.0 && s.target_axial_strain < 1.0))
        return "target_axial_strain: " + format_number(s.target_axial_strain) + " must lie in (0, 1)";
    if (!positive(s.plate_speed_m_per_s))
        return "plate_speed_m_per_s: " + format_number(s.plate_speed_m_per_s) + " must be > 0";
    if (!non_negative(s.pressure_ramp_time_s))
        return "pressure_ramp_time_s: " + format_number(s.pressure_ramp_time_s) + " must be ≥ 0";
    if (!non_negative(s.hold_time_s)) return "hold_time_s: " + format_number(s.hold_time_s) + " must be ≥ 0";
    if (s.max_hold_time_s && !(std::isfinite(*s.max_hold_time_s) && *s.max_hold_time_s >= s.hold_time_s))
        return "max_hold_time_s: " + format_number(*s.max_hold_time_s) + " must be ≥ hold_time_s "
             + format_number(s.hold_time_s);
    if (s.pressure_ramp_time_s + s.hold_time_s <= 0.0)
        return "pressure_ramp_time_s + hold_time_s must be > 0: the column needs time under σ₃ before loading";
    if (!positive(s.sample_interval_s))
        return "sample_interval_s: " + format_number(s.sample_interval_s) + " must be > 0";
    for (double e : s.snapshot_strains)
        if (!std::isfinite(e)) return "snapshot_strains: every strain must be finite";
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

/// Sorted, de-duplicated snapshot strains within [0, target], always with 0 and target.
std::vector<double> snapshot_plan(const TriaxialSettings& s)
{
    std::vector<double> plan{0.0, s.target_axial_strain};
    for (double e : s.snapshot_strains) plan.push_back(std::clamp(e, 0.0, s.target_axial_strain));
    std::sort(plan.begin(), plan.end());
    plan.erase(std::unique(plan.begin(), plan.end()), plan.end());
    return plan;
}

} // namespace

void TriaxialSeries::push_back(const TriaxialSample& s)
{
    time_s.push_back(s.time_s);
    phase.push_back(static_cast<std::uint8_t>(s.phase));
    axial_strain.push_back(s.axial_strain);
    height_m.push_back(s.height_m);
    top_plate_force_n.push_back(s.top_plate_force_n);
    bottom_plate_force_n.push_back(s.bottom_plate_force_n);
    column_radius_m.push_back(s.column_radius_m);
    confining_pressure_pa.push_back(s.confining_pressure_pa);
    sigma1_pa.push_back(s.sigma1_pa);
    sigma3_effective_pa.push_back(s.sigma3_effective_pa);
    deviatoric_stress_pa.push_back(s.deviatoric_stress_pa);
    stress_ratio.push_back(s.stress_ratio);
    kinetic_energy_j.push_back(s.kinetic_energy_j);
    elastic_energy_j.push_back(s.elastic_energy_j);
    contacts.push_back(s.contacts);
    sliding_contacts.push_back(s.sliding_contacts);
    membrane_contacts.push_back(s.membrane_contacts);
    wire_strain_mean.push_back(s.wire_strain_mean);
    wire_strain_max.push_back(s.wire_strain_max);
    inertial_number.push_back(s.inertial_number);
}

QuasiStaticVerdict quasi_static_verdict(const TriaxialSeries& s, std::size_t loading_start)
{
    QuasiStaticVerdict v;
    double ratio_sum = 0.0;
    std::size_t rows = 0;
    for (std::size_t i = loading_start; i < s.size(); ++i, ++rows) {
        v.max_inertial_number = std::max(v.max_inertial_number, s.inertial_number[i]);
        const double ratio = s.elastic_energy_j[i] > 0.0 ? s.kinetic_energy_j[i] / s.elastic_energy_j[i]
                                                         : std::numeric_limits<double>::infinity();
        v.max_kinetic_to_elastic = std::max(v.max_kinetic_to_elastic, ratio);
        ratio_sum += ratio;
    }
    v.mean_kinetic_to_elastic = rows > 0 ? ratio_sum / static_cast<double>(rows) : 0.0;
    if (v.max_inertial_number > max_quasi_static_inertial_number)
        v.warning = "inertial number reached " + format_number(v.max_inertial_number) + " (quasi-static below "
                  + format_number(max_quasi_static_inertial_number) + ")";
    if (v.mean_kinetic_to_elastic > max_quasi_static_energy_ratio)
        v.warning += std::string(v.warning.empty() ? "" : "; ") + "kinetic/elastic energy averaged "
                   + format_number(v.mean_kinetic_to_elastic) + " over the loading (quasi-static below "
                   + format_number(max_quasi_static_energy_ratio) + ")";
    v.quasi_static = v.warning.empty();
    return v;
}

double consolidation_window_mean(const TriaxialSeries& s, const std::vector<double>& column, std::size_t last)
{
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = last + 1; i-- > 0 && s.time_s[i] >= s.time_s[last] - consolidation_window_s; ++n)
        sum += column[i];
    return sum / static_cast<double>(n);
}

std::optional<LoadingStart> loading_start(const TriaxialSeries& s)
{
    const auto loading = static_cast<std::uint8_t>(TriaxialPhase::loading);
    const auto row = std::find(s.phase.begin(), s.phase.end(), loading);
    if (row == s.phase.end()) return std::nullopt;
    LoadingStart l;
    l.sample = static_cast<std::size_t>(row - s.phase.begin());
    l.sigma1_pa = consolidation_window_mean(s, s.sigma1_pa, l.sample);
    l.sigma3_effective_pa = consolidation_window_mean(s, s.sigma3_effective_pa, l.sample);
    l.stress_ratio = analysis::stress_ratio(l.sigma1_pa, l.sigma3_effective_pa);
    const double h_first = s.height_m.front();
    const double h_min = *std::min_element(s.height_m.begin(), s.height_m.begin() + static_cast<std::ptrdiff_t>(l.sample) + 1);
    l.axial_strain = analysis::axial_strain(h_first, s.height_m[l.sample]);
    l.rebound_axial_strain = (s.height_m[l.sample] - h_min) / h_first;
    l.radial_strain = (s.column_radius_m.front() - s.column_radius_m[l.sample]) / s.column_radius_m.front();
    return l;
}

bool within_consolidation_mismatch(double sigma1_pa, double target_pa) noexcept
{
    return std::isfinite(sigma1_pa) && std::isfinite(target_pa)
        && std::abs(sigma1_pa - target_pa) <= max_consolidation_mismatch * std::abs(target_pa);
}

const char* to_string(Consolidation c) noexcept
{
    return c == Consolidation::effective ? "effective" : "cell_pressure";
}

std::optional<Consolidation> consolidation_from_string(std::string_view text) noexcept
{
    for (const Consolidation c : {Consolidation::cell_pressure, Consolidation::effective})
        if (text == to_string(c)) return c;
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
    return s.target_axial_strain * height_m / s.plate_speed_m_per_s;
}

std::uint64_t expected_triaxial_steps(const TriaxialSettings& s, double height_m, double dt_s)
{
    // The longest hold: progress never passes 100 % while σ₃ is held longer
    // than hold_time_s; run_triaxial re-counts when the loading starts.
    const auto pre_load = static_cast<std::uint64_t>(std::ceil((s.pressure_ramp_time_s + longest_hold_s(s)) / dt_s));
    return pre_load + static_cast<std::uint64_t>(std::ceil(loading_time_s(s, height_m) / dt_s));
}

std::vector<double> volumetric_strains(const TriaxialSeries& s, double initial_volume_m3)
{
    std::vector<double> e(s.size());
    for (std::size_t i = 0; i < s.size(); ++i)
        e[i] = analysis::volumetric_strain(
            initial_volume_m3, analysis::cylinder_volume_m3(s.column_radius_m[i], s.height_m[i]));
    return e;
}

TriaxialSample measure_triaxial_sample(const World& w, ThreadPool& pool, std::size_t top_plate_wall,
    std::size_t bottom_plate_wall, double initial_height_m)
{
    TriaxialSample s;
    const Wall& top = w.walls[top_plate_wall];
    const Wall& bottom = w.walls[bottom_plate_wall];
    s.height_m = top.point_m.z() - bottom.point_m.z();
    s.axial_strain = analysis::axial_strain(initial_height_m, s.height_m);
    s.top_plate_force_n = plate_compression_n(w, top_plate_wall);
    s.bottom_plate_force_n = plate_compression_n(w, bottom_plate_wall);

    // Column radius (the model spec §6.3): grains touching the membrane, each
    // counted once. The grain–membrane pairs are one group of the list,
    // sorted by (grain, node) (pair_key), so a grain's are consecutive.
    const TranslationalState& grains = w.of(BodyKind::grain);
    const ContactList& c = w.contacts;
    std::vector<double> radial_m;
    std::uint32_t previous = std::numeric_limits<std::uint32_t>::max();
    for (std::size_t p = 0; p < c.size(); ++p) {
        if (!c.touching[p] || c.first[p].kind() != BodyKind::grain || c.second[p].kind() != BodyKind::membrane) continue;
        const std::uint32_t g = c.first[p].index();
        if (g == previous) continue;
        previous = g;
        const Vec3& x = grains.x[0][g];
        radial_m.push_back(std::hypot(x.x(), x.y()));
    }
    double radius_sum_m = 0.0, enclosing_m = 0.0;
    for (std::size_t i = 0; i < grains.size(); ++i) {
        radius_sum_m += grains.radius_m[i];
        const Vec3& x = grains.x[0][i];
        enclosing_m = std::max(enclosing_m, std::hypot(x.x(), x.y()) + grains.radius_m[i]);
    }
    const double mean_grain_radius_m = grains.size() ? radius_sum_m / static_cast<double>(grains.size()) : 0.0;
    s.column_radius_m = analysis::column_radius_m(radial_m, mean_grain_radius_m).value_or(enclosing_m);

    const MembraneLoad load = membrane_contact_load(w, pool);
    s.membrane_contacts = load.contacts;
    s.sigma1_pa = analysis::axial_stress_pa(s.top_plate_force_n, s.column_radius_m);
    s.sigma3_effective_pa = analysis::effective_confining_pressure_pa(load.normal_force_n, s.column_radius_m, s.height_m);
    s.deviatoric_stress_pa = analysis::deviatoric_stress_pa(s.sigma1_pa, s.sigma3_effective_pa);
    s.stress_ratio = analysis::stress_ratio(s.sigma1_pa, s.sigma3_effective_pa);
    s.volume_m3 = analysis::cylinder_volume_m3(s.column_radius_m, s.height_m);
    s.kinetic_energy_j = kinetic_energy_j(w, pool);
    s.elastic_energy_j = elastic_energy(w, pool).total_j(); // held bodies carry none

    struct Count {
        std::uint64_t touching = 0, sliding = 0;
    };
    const Count pairs = reduce_blocks(
        pool, c.size(), Count{},
        [&](std::size_t b, std::size_t e) {
            Count n;
            for (std::size_t p = b; p < e; ++p)
                if (c.touching[p]) {
                    ++n.touching;
                    if (!c.tangential[p].sticking) ++n.sliding;
                }
            return n;
        },
        [](Count a, const Count& b) {
            a.touching += b.touching;
            a.sliding += b.sliding;
            return a;
        });
    s.contacts = pairs.touching; // body pairs and body–wall contacts
    s.sliding_contacts = pairs.sliding;

    const std::vector<double>& strain = w.wire_forces.segment_strain;
    if (!strain.empty()) {
        double sum = 0.0, max = strain.front();
        for (double e : strain) {
            sum += e;
            max = std::max(max, e);
        }
        s.wire_strain_mean = sum / static_cast<double>(strain.size());
        s.wire_strain_max = max;
    }
    return s;
}

TriaxialSnapshot take_triaxial_snapshot(const World& w)
{
    TriaxialSnapshot snap;
    const TranslationalState& g = w.of(BodyKind::grain);
    snap.grain_position_m = g.x[0];
    snap.grain_radius_m = g.radius_m;
    snap.grain_velocity_m_per_s.reserve(g.size());
    for (const Vec3& v : g.x[1]) snap.grain_velocity_m_per_s.push_back(v / w.dt_s);
    snap.wire_node_position_m = w.of(BodyKind::wire).x[0];
    snap.wire_segment_strain = w.wire_forces.segment_strain;
    snap.membrane_node_position_m = w.of(BodyKind::membrane).x[0];
    snap.membrane_triangles = w.membrane.triangles;

    ForceNetwork& f = snap.forces;
    const ContactList& c = w.contacts;
    for (std::size_t p = 0; p < c.pair_count(); ++p) {
        if (!c.touching[p]) continue;
        f.first.push_back(c.first[p]);
        f.second.push_back(c.second[p]);
        f.force_n.push_back(c.output[p].force_n);
        f.normal_force_n.push_back(c.output[p].normal_force_n);
    }
    for (std::size_t p = c.pair_count(); p < c.size(); ++p) { // by wall, then body
        if (c.output[p].force_n.isZero(0.0)) continue;
        f.wall.push_back(c.second[p].index());
        f.wall_body.push_back(c.first[p]);
        f.wall_force_n.push_back(c.output[p].force_n);
    }
    return snap;
}

Result<TriaxialResult, std::string> run_triaxial(
    Simulation& sim, std::size_t top_plate_wall, const TriaxialSettings& settings, const RunControl& control)
{
    return run_triaxial(sim, top_plate_wall, settings, control, {});
}

Result<TriaxialResult, std::string> run_triaxial(Simulation& sim, std::size_t top_plate_wall,
    const TriaxialSettings& settings, const RunControl& control, TriaxialContinuation continuation)
{
    const auto wall_start = std::chrono::steady_clock::now();
    World& w = sim.world;
    ThreadPool& pool = sim.pool();
    if (auto e = validate(w, top_plate_wall, settings)) return Err(*e);
    constexpr std::size_t bottom_plate_wall = 0;
    TranslationalState& nodes = w.of(BodyKind::membrane);
    const auto plates_apart_m = [&] {
        return w.walls[top_plate_wall].point_m.z() - w.walls[bottom_plate_wall].point_m.z();
    };

    // Everything that changes from step to step outside the World; the
    // lambdas below read and write it only (a checkpoint saves it).
    const bool continued = continuation.from.has_value();
    TriaxialDriverState st = continued ? std::move(*continuation.from) : TriaxialDriverState{};
    TriaxialResult& result = st.result;
    if (!continued) {
        // 1. Deformable membrane; the part at and above the top plate is sealed to the cap.
        set_membrane_rigid(w, false);
        const double plate_z = w.walls[top_plate_wall].point_m.z();
        for (std::uint32_t i = 0; i < nodes.size(); ++i) {
            if (nodes.x[0][i].z() + nodes.radius_m[i] <= plate_z) continue;
            set_motion(w, {BodyKind::membrane, i}, Motion::kinematic); // moves with the plate, below
            set_velocity(w, {BodyKind::membrane, i}, Vec3::Zero());
            st.cap_nodes.push_back(i);
        }
        if (settings.real_weights)
            set_weights(w, settings.real_weights->density_scale, settings.real_weights->wire_mass_scale, 1.0);
        w.membrane.pressure_pa = 0.0;
        w.walls[top_plate_wall].velocity_m_per_s.setZero();
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
    const TranslationalState& grains = w.of(BodyKind::grain);
    double radius_sum_m = 0.0;
    for (double r : grains.radius_m) radius_sum_m += r;
    const double grain_radius_m = radius_sum_m / static_cast<double>(grains.size());
    const double grain_density = w.materials[grains.material[0]].density_kg_per_m3;

    const double pre_load_s = settings.pressure_ramp_time_s + settings.hold_time_s;
    const auto pre_load_steps = static_cast<std::uint64_t>(std::ceil(pre_load_s / dt));
    const auto sample_every = static_cast<std::uint64_t>(std::max(1.0, std::round(settings.sample_interval_s / dt)));
    const std::vector<double> plan = snapshot_plan(settings);
    if (continued
        && (st.next_snapshot > plan.size() || (st.loading && st.loading_start_sample >= result.series.size())
            || !(st.reference_height_m > 0.0) || !(st.column_radius_m > 0.0)))
        return Err(std::string("the test's saved state is inconsistent (snapshot plan, loading start or heights)"));
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
        while (st.next_snapshot < plan.size() && strain >= plan[st.next_snapshot]) {
            TriaxialSnapshot snap = take_triaxial_snapshot(w);
            snap.requested_axial_strain = plan[st.next_snapshot];
            snap.axial_strain = strain;
            snap.time_s = static_cast<double>(st.steps) * dt;
            result.snapshots.push_back(std::move(snap));
            ++st.next_snapshot;
        }
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
        const double net_down_n = target_n - plate_compression_n(w, top_plate_wall);
        double& v = w.walls[top_plate_wall].velocity_m_per_s.z();
        v = std::clamp(v - dt * net_down_n / piston_mass_kg, -max_piston_speed, max_piston_speed);
    };
    // One step: σ₃ for the time reached, the cap nodes carried with the plate.
    // A checkpoint may be taken before it (not before the first step of this
    // run: that state is the one the run started from), also when the run is
    // about to be cancelled: a host saves on its way out.
    bool first_of_run = true;
    auto advance = [&]() -> std::optional<std::string> {
        if (continuation.between_steps && !first_of_run) {
            st.wall_time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
            continuation.between_steps(w, st);
            st.wall_time_s -= std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
        }
        first_of_run = false;
        if (control.cancel && control.cancel->load(std::memory_order_relaxed))
            return "cancelled after " + std::to_string(st.steps) + " steps of the triaxial test";
        const std::uint64_t n = st.steps;
        w.membrane.pressure_pa = ramped_pressure_pa(
            settings.confining_pressure_pa, static_cast<double>(n + 1) * dt, settings.pressure_ramp_time_s);
        if (!st.loading) follow_the_pressure();
        const Vec3 v = w.walls[top_plate_wall].velocity_m_per_s;
        for (std::uint32_t i : st.cap_nodes) set_velocity(w, {BodyKind::membrane, i}, v);
        const StepReport report = sim.step();
        ++st.steps;
        if (report.blew_up)
            return "the simulation blew up after " + std::to_string(st.steps)
                 + " steps of the triaxial test (time step too large for the loading?)";
        if (control.progress && control.progress_every > 0 && st.steps % control.progress_every == 0) {
            const auto [done, total] = triaxial_progress(st);
            control.progress(done, total);
        }
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
        const double max_hold_s = longest_hold_s(settings);
        const auto max_pre_load_steps
            = static_cast<std::uint64_t>(std::ceil((settings.pressure_ramp_time_s + max_hold_s) / dt));
        const auto window_steps = static_cast<std::uint64_t>(std::max(1.0, std::round(consolidation_window_s / dt)));
        auto consolidated = [&] {
            const double s3 = consolidation_target_pa();
            return st.window_sigma1_pa && std::abs(*st.window_sigma1_pa - s3) <= consolidated_mismatch * s3
                && std::abs(w.walls[top_plate_wall].velocity_m_per_s.z()) <= settings.plate_speed_m_per_s;
        };
        while (st.steps < pre_load_steps || (st.steps < max_pre_load_steps && !consolidated())) {
            if (auto e = advance()) return Err(*e);
            st.window_force_n += plate_compression_n(w, top_plate_wall);
            if (++st.window_filled == window_steps) {
                st.window_sigma1_pa = analysis::axial_stress_pa(
                    st.window_force_n / static_cast<double>(window_steps), st.column_radius_m);
                st.window_force_n = 0.0;
                st.window_filled = 0;
            }
        }
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
    bool stopped_early = false;
    for (;;) {
        if (auto e = advance()) return Err(*e);
        const double strain = snapshot_due();
        if (strain >= settings.target_axial_strain) break;
        if (control.after_step && !control.after_step(w, StepReport{})) {
            stopped_early = true;
            break;
        }
    }
    w.walls[top_plate_wall].velocity_m_per_s.setZero();
    if (st.last_sample_step != st.steps) sample(); // the end of the test is always a row

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
        result.warnings.push_back("no valid deviatoric stress sample during loading: no peak");
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
            result.warnings.push_back("test at σ₃ = " + format_number(settings.confining_pressure_pa)
                                      + " Pa: no yield state: " + reading.error());
        }
    }

    QuasiStaticVerdict& v = result.verdict;
    v = quasi_static_verdict(ts, loading_start_sample);
    if (!v.quasi_static) {
        v.warning = "test at σ₃ = " + format_number(settings.confining_pressure_pa) + " Pa was not quasi-static: " + v.warning
                  + "; lower the plate speed or the density scaling";
        result.warnings.push_back(v.warning);
    }
    if (stopped_early)
        result.warnings.push_back("stopped by the host at axial strain " + format_number(ts.axial_strain.back())
                                  + " before the target " + format_number(settings.target_axial_strain));

    result.steps = st.steps;
    result.simulated_time_s = static_cast<double>(st.steps) * dt;
    result.wall_time_s
        = st.wall_time_s + std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return std::move(result);
}

} // namespace wiredem::engine
