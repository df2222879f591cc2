// The rigid-wall triaxial cell; see cuboid.hpp.
#include "triaxial/cuboid.hpp"

#include "analysis/stress.hpp"
#include "contact/geometry.hpp"
#include "specimen/packing.hpp"
#include "specimen/preparation.hpp"
#include "timestep.hpp"
#include "triaxial/consolidation.hpp"
#include "triaxial/loading.hpp"
#include "triaxial/pressure.hpp"
#include "triaxial/sampling.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

namespace wiredem::engine {
namespace {

bool is_plane(const World& w, std::size_t wall, const Vec3& normal)
{
    return wall < w.walls.size() && w.walls[wall].shape == Wall::Shape::plane && w.walls[wall].normal.isApprox(normal);
}

/// The wall's signed coordinate along its own axis (x, y or z).
double wall_at_m(const World& w, std::size_t wall, int axis) { return w.walls[wall].point_m[axis]; }

} // namespace

CuboidWalls add_cuboid_walls(World& w, const Vec3& lo_m, const Vec3& hi_m, std::uint8_t material,
    std::optional<double> friction_coeff)
{
    auto plane = [&](const Vec3& point, const Vec3& normal) {
        Wall wall;
        wall.shape = Wall::Shape::plane;
        wall.point_m = point;
        wall.normal = normal;
        wall.material = material;
        wall.friction_coeff = friction_coeff;
        return add_wall(w, wall);
    };
    CuboidWalls c;
    c.bottom = plane(lo_m, Vec3::UnitZ());
    c.top = plane(hi_m, -Vec3::UnitZ());
    c.lateral[0] = plane(lo_m, Vec3::UnitX());
    c.lateral[1] = plane(hi_m, -Vec3::UnitX());
    c.lateral[2] = plane(lo_m, Vec3::UnitY());
    c.lateral[3] = plane(hi_m, -Vec3::UnitY());
    return c;
}

double servo_wall_speed_m_per_s(double target_pa, double measured_pa, double area_m2, const WallResponse& response,
    double dt_s, double relaxation, double max_speed_m_per_s) noexcept
{
    const double force_error_n = (target_pa - measured_pa) * area_m2;
    // The force follows a change of the wall's speed v within the step by
    // (k_w δt + c_w) v: the springs over the step, the dashpots at once.
    const double per_speed = response.stiffness_n_per_m * dt_s + response.damping_n_s_per_m;
    if (!(per_speed > 0.0)) return force_error_n > 0.0 ? max_speed_m_per_s : 0.0;
    const double v = relaxation * force_error_n / per_speed;
    return std::clamp(v, -max_speed_m_per_s, max_speed_m_per_s);
}

WallResponse wall_response(const World& w, std::size_t wall)
{
    const ContactList& c = w.contacts;
    WallResponse r;
    if (wall + 1 >= c.wall_start.size()) return r;
    for (std::size_t p = c.wall_start[wall]; p < c.wall_start[wall + 1]; ++p) {
        if (!c.touching[p]) continue;
        // F = c (ξ^{3/2} + γ_n √ξ dξ/dt): dF/dξ = (3/2) c √ξ, dF/d(dξ/dt) = c γ_n √ξ.
        const double c_sqrt_xi = c.hertz_coefficient[p] * std::sqrt(c.output[p].overlap_m);
        r.stiffness_n_per_m += 1.5 * c_sqrt_xi;
        r.damping_n_s_per_m += w.contact.normal_damping_s * c_sqrt_xi;
    }
    return r;
}

CuboidStresses cuboid_stresses(const World& w, const CuboidWalls& walls)
{
    CuboidStresses s;
    s.width_x_m = wall_at_m(w, walls.lateral[1], 0) - wall_at_m(w, walls.lateral[0], 0);
    s.width_y_m = wall_at_m(w, walls.lateral[3], 1) - wall_at_m(w, walls.lateral[2], 1);
    s.height_m = wall_at_m(w, walls.top, 2) - wall_at_m(w, walls.bottom, 2);
    const std::array<double, 4> face_m2{s.width_y_m * s.height_m, s.width_y_m * s.height_m,
        s.width_x_m * s.height_m, s.width_x_m * s.height_m};
    for (std::size_t i = 0; i < 4; ++i) {
        s.lateral_pa[i] = plate_compression_n(w, walls.lateral[i]) / face_m2[i];
        s.lateral_contacts += w.wall_loads[walls.lateral[i]].contacts;
    }
    s.sigma_x_pa = 0.5 * (s.lateral_pa[0] + s.lateral_pa[1]);
    s.sigma_y_pa = 0.5 * (s.lateral_pa[2] + s.lateral_pa[3]);
    s.sigma_z_pa = plate_compression_n(w, walls.top) / (s.width_x_m * s.width_y_m);
    return s;
}

Eigen::Matrix3d love_weber_stress_pa(const World& w, double volume_m3)
{
    const ContactList& c = w.contacts;
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
    for (std::size_t p = 0; p < c.pair_count(); ++p) {
        if (!c.touching[p]) continue;
        const Vec3 branch = w.of(c.second[p].kind()).x[0][c.second[p].index()] - w.of(c.first[p].kind()).x[0][c.first[p].index()];
        sum += branch * c.output[p].force_n.transpose();
    }
    for (std::size_t p = c.pair_count(); p < c.size(); ++p) {
        if (!c.touching[p]) continue;
        const Vec3& x = w.of(c.first[p].kind()).x[0][c.first[p].index()];
        const auto [gap_m, towards] = wall_gap(w.walls[c.second[p].index()], x);
        sum += (gap_m * towards) * c.output[p].force_n.transpose(); // to the wall's surface
    }
    return -sum / volume_m3;
}

double love_weber_inertia_bound_pa(const World& w, double volume_m3)
{
    Vec3 centroid = Vec3::Zero();
    std::size_t n = 0;
    for (int k = 0; k < body_kind_count; ++k)
        for (const Vec3& x : w.bodies[k].x[0]) centroid += x, ++n;
    if (n == 0) return 0.0;
    centroid /= static_cast<double>(n);
    double sum = 0.0;
    for (int k = 0; k < body_kind_count; ++k) {
        const TranslationalState& b = w.bodies[k];
        for (std::size_t i = 0; i < b.size(); ++i)
            if (is_dynamic(b, i)) sum += (b.x[0][i] - centroid).norm() * w.body_force_n[k][i].norm();
    }
    return sum / volume_m3;
}

std::optional<std::string> validate_cuboid_settings(const CuboidSettings& s)
{
    if (auto e = validate_triaxial_settings(s.triaxial)) return e;
    if (!(s.servo_relaxation > 0.0 && s.servo_relaxation <= 1.0))
        return "servo_relaxation: " + format_number(s.servo_relaxation)
             + " must lie in (0, 1] (above 1 the servo overshoots, above 2 it is unstable)";
    return std::nullopt;
}

Result<CuboidResult, std::string> run_cuboid_triaxial(Simulation& sim, const CuboidWalls& walls,
    const CuboidSettings& cuboid, const RunControl& control, CuboidContinuation continuation)
{
    const auto wall_start = std::chrono::steady_clock::now();
    World& w = sim.world;
    ThreadPool& pool = sim.pool();
    const TriaxialSettings& settings = cuboid.triaxial;
    if (auto e = validate_cuboid_settings(cuboid)) return Err(*e);
    if (!is_plane(w, walls.bottom, Vec3::UnitZ()) || !is_plane(w, walls.top, -Vec3::UnitZ())
        || !is_plane(w, walls.lateral[0], Vec3::UnitX()) || !is_plane(w, walls.lateral[1], -Vec3::UnitX())
        || !is_plane(w, walls.lateral[2], Vec3::UnitY()) || !is_plane(w, walls.lateral[3], -Vec3::UnitY()))
        return Err(std::string("the cuboid's walls must be planes with their normals inwards: bottom +z, top −z, "
                               "lateral +x, −x, +y, −y"));
    if (w.of(BodyKind::grain).size() == 0) return Err(std::string("the world has no grains"));
    if (w.of(BodyKind::membrane).size() != 0)
        return Err(std::string("the cuboid cell has no membrane, but the world has one"));
    if (!(w.dt_s > 0.0)) return Err(std::string("the time step is not set"));
    {
        const CuboidStresses box = cuboid_stresses(w, walls);
        if (!(box.width_x_m > 0.0 && box.width_y_m > 0.0 && box.height_m > 0.0))
            return Err(std::string("the cuboid's walls do not enclose a box (a wall is beyond its opposite)"));
    }
    const double dt = w.dt_s;
    const StableStep crit = stable_time_step(w);
    if (dt > crit.critical_s)
        return Err("time step " + format_number(dt) + " s exceeds the stable limit " + format_number(crit.critical_s)
                   + " s set by the " + crit.limited_by);
    if (crit.overdamped()) return Err(overdamped_error(crit, w.contact.normal_damping_s));

    // Everything that changes from step to step outside the World (a
    // checkpoint saves it): the rows, the phase, the consolidation window.
    const bool continued = continuation.from.has_value();
    CuboidDriverState cst = continued ? std::move(*continuation.from) : CuboidDriverState{};
    TriaxialDriverState& st = cst.triaxial;
    TriaxialResult& result = st.result;
    if (!continued) {
        if (settings.real_weights)
            set_weights(w, settings.real_weights->density_scale, settings.real_weights->wire_mass_scale, 1.0);
        for (const std::size_t i : {walls.bottom, walls.top, walls.lateral[0], walls.lateral[1], walls.lateral[2], walls.lateral[3]})
            w.walls[i].velocity_m_per_s.setZero();
    }

    // A clump counts once, at its volume-equivalent radius.
    const TranslationalState& grains = w.of(BodyKind::grain);
    const double grain_radius_m = mean_grain_radius_m(w);
    const double grain_density = w.materials[grains.material[0]].density_kg_per_m3;

    const auto pre_load_steps = static_cast<std::uint64_t>(std::ceil((settings.pressure_ramp_time_s + settings.hold_time_s) / dt));
    const auto sample_every = static_cast<std::uint64_t>(std::max(1.0, std::round(settings.sample_interval_s / dt)));
    const std::vector<double> plan = snapshot_plan(settings.target_axial_strain, settings.snapshot_strains);
    const auto height_m = [&] { return wall_at_m(w, walls.top, 2) - wall_at_m(w, walls.bottom, 2); };
    if (continued) {
        const std::size_t rows = result.series.size();
        if (cst.width_x_m.size() != rows || cst.width_y_m.size() != rows || cst.sigma_x_pa.size() != rows
            || cst.sigma_y_pa.size() != rows || st.next_snapshot > plan.size() || (st.loading && st.loading_start_sample >= rows)
            || !(st.reference_height_m > 0.0) || !st.cap_nodes.empty()
            || st.steps > std::numeric_limits<std::uint64_t>::max() / 2)
            return Err(std::string("the cuboid test's saved state is inconsistent (rows, snapshot plan, loading start or height)"));
    } else {
        st.reference_height_m = height_m();
        st.expected_steps = expected_triaxial_steps(settings, st.reference_height_m, dt);
        result.time_step_s = dt;
    }
    double sigma3_pa = 0.0; // σ₃ of the ramp at the step being taken

    // A row (sampling.hpp) with the walls' stresses (cuboid.hpp's file comment).
    auto sample = [&] {
        const CuboidStresses box = cuboid_stresses(w, walls);
        TriaxialSample s;
        s.time_s = static_cast<double>(st.steps) * dt;
        s.phase = st.loading ? TriaxialPhase::loading
                             : (s.time_s < settings.pressure_ramp_time_s ? TriaxialPhase::ramp : TriaxialPhase::hold);
        s.height_m = box.height_m;
        s.axial_strain = analysis::axial_strain(st.reference_height_m, box.height_m);
        s.top_plate_force_n = plate_compression_n(w, walls.top);
        s.bottom_plate_force_n = plate_compression_n(w, walls.bottom);
        s.column_radius_m = std::sqrt(box.width_x_m * box.width_y_m / std::numbers::pi);
        s.confining_pressure_pa = sigma3_pa;
        s.sigma1_pa = analysis::axial_stress_pa(s.top_plate_force_n, s.column_radius_m);
        s.sigma3_effective_pa = 0.5 * (box.sigma_x_pa + box.sigma_y_pa);
        s.deviatoric_stress_pa = analysis::deviatoric_stress_pa(s.sigma1_pa, s.sigma3_effective_pa);
        s.stress_ratio = analysis::stress_ratio(s.sigma1_pa, s.sigma3_effective_pa);
        s.volume_m3 = analysis::cylinder_volume_m3(s.column_radius_m, s.height_m);
        s.membrane_contacts = box.lateral_contacts;
        measure_energies_and_contacts(w, pool, s);
        if (st.loading)
            s.inertial_number = analysis::inertial_number(
                settings.plate_speed_m_per_s / st.reference_height_m, grain_radius_m, grain_density, sigma3_pa);
        result.series.push_back(s);
        cst.width_x_m.push_back(box.width_x_m);
        cst.width_y_m.push_back(box.width_y_m);
        cst.sigma_x_pa.push_back(box.sigma_x_pa);
        cst.sigma_y_pa.push_back(box.sigma_y_pa);
        st.last_sample_step = st.steps;
        st.column_radius_m = s.column_radius_m;
    };
    auto snapshot_due = [&] {
        const double strain = analysis::axial_strain(st.reference_height_m, height_m());
        take_due_snapshots(w, plan, st.next_snapshot, strain, static_cast<double>(st.steps) * dt, result.snapshots);
        return strain;
    };
    // Consolidation (consolidation.hpp): the top wall is brought to σ₃, or
    // to the lateral walls' σ₃ averaged over the last window of rows.
    auto effective_sigma3_pa = [&]() -> std::optional<double> {
        if (result.series.size() == 0) return std::nullopt;
        const TriaxialSeries& rows = result.series;
        const double s3 = consolidation_window_mean(rows, rows.sigma3_effective_pa, rows.size() - 1);
        if (std::isfinite(s3) && s3 > 0.0) return s3;
        return std::nullopt;
    };
    auto consolidation_target_pa = [&] {
        if (settings.consolidation == Consolidation::effective)
            if (const std::optional<double> s3 = effective_sigma3_pa()) return *s3;
        return sigma3_pa;
    };
    const double max_wall_speed = max_piston_speed_factor * settings.plate_speed_m_per_s;
    // One servo step for a wall towards `target_pa` (cuboid.hpp).
    auto servo = [&](std::size_t wall, double target_pa, double measured_pa, double area_m2) {
        const double v = servo_wall_speed_m_per_s(
            target_pa, measured_pa, area_m2, wall_response(w, wall), dt, cuboid.servo_relaxation, max_wall_speed);
        w.walls[wall].velocity_m_per_s = v * w.walls[wall].normal;
    };
    // The stepper hands its host the membrane cell's part of the state; the
    // host saves the whole of it.
    using Stepper = ColumnTestStepper<TriaxialDriverState>;
    const Stepper::BetweenSteps between_steps = continuation.between_steps
        ? Stepper::BetweenSteps([&](const World& world, const TriaxialDriverState&) { continuation.between_steps(world, cst); })
        : Stepper::BetweenSteps{};
    Stepper stepper(sim, control, between_steps, st, "the cuboid triaxial test", wall_start);
    auto advance = [&]() -> std::optional<std::string> {
        auto prescribe = [&] {
            sigma3_pa = ramped_pressure_pa(
                settings.confining_pressure_pa, static_cast<double>(st.steps + 1) * dt, settings.pressure_ramp_time_s);
            const CuboidStresses box = cuboid_stresses(w, walls);
            const double face_x = box.width_y_m * box.height_m, face_y = box.width_x_m * box.height_m;
            for (std::size_t i = 0; i < 4; ++i) servo(walls.lateral[i], sigma3_pa, box.lateral_pa[i], i < 2 ? face_x : face_y);
            if (!st.loading) servo(walls.top, consolidation_target_pa(), box.sigma_z_pa, box.width_x_m * box.width_y_m);
        };
        if (auto e = stepper.step(prescribe, [&] { return triaxial_progress(st); })) return e;
        if ((st.steps - 1) % sample_every == 0) sample();
        return std::nullopt;
    };

    if (!st.loading) {
        // 1. Ramp and hold, the top wall following the consolidation target, as
        // the membrane cell does (run_triaxial): at least hold_time_s, then until
        // consolidated, at most the longest hold.
        if (auto e = hold_until_consolidated(w, walls.top, settings, st, pre_load_steps, advance, consolidation_target_pa))
            return Err(*e);
        result.hold_time_s = static_cast<double>(st.steps) * dt - settings.pressure_ramp_time_s;

        // 2. Loading at constant speed from h₀ now.
        st.reference_height_m = height_m();
        result.initial_height_m = st.reference_height_m;
        const double target_pa = consolidation_target_pa();
        st.loading = true;
        st.expected_steps = st.steps + static_cast<std::uint64_t>(std::ceil(loading_time_s(settings, st.reference_height_m) / dt));
        st.loading_start_step = st.steps;
        if (st.last_sample_step == st.steps) { // this step's row belongs to the loading
            result.series.phase.back() = static_cast<std::uint8_t>(TriaxialPhase::loading);
            result.series.axial_strain.back() = 0.0;
            result.series.inertial_number.back() = analysis::inertial_number(
                settings.plate_speed_m_per_s / st.reference_height_m, grain_radius_m, grain_density, sigma3_pa);
        } else {
            sample();
        }
        st.loading_start_sample = result.series.size() - 1;
        result.consolidated_sigma1_pa = st.window_sigma1_pa.value_or(result.series.sigma1_pa[st.loading_start_sample]);
        result.consolidation = settings.consolidation;
        result.consolidation_target_pa = target_pa;
        if (!within_consolidation_mismatch(result.consolidated_sigma1_pa, target_pa))
            result.warnings.push_back("test at σ₃ = " + format_number(settings.confining_pressure_pa)
                                      + " Pa had not consolidated when loading started: σ₁ = "
                                      + format_number(result.consolidated_sigma1_pa) + " Pa, more than "
                                      + format_number(100 * max_consolidation_mismatch) + " % off "
                                      + format_number(target_pa) + " Pa after a hold of " + format_number(result.hold_time_s)
                                      + " s; lengthen hold_time_s or max_hold_time_s");
        snapshot_due();
        w.walls[walls.top].velocity_m_per_s = Vec3(0.0, 0.0, -settings.plate_speed_m_per_s);
    }
    const auto end = load_to_target(w, control, settings.target_axial_strain, advance, snapshot_due, [](double) { return false; });
    if (!end.ok()) return Err(end.error());
    for (const std::size_t i : {walls.top, walls.lateral[0], walls.lateral[1], walls.lateral[2], walls.lateral[3]})
        w.walls[i].velocity_m_per_s.setZero();
    if (st.last_sample_step != st.steps) sample(); // the end of the test is always a row

    read_loading(result, settings.confining_pressure_pa, st.loading_start_sample, st.reference_height_m);
    if (end.value() == LoadingEnd::host)
        result.warnings.push_back("stopped by the host at axial strain " + format_number(result.series.axial_strain.back())
                                  + " before the target " + format_number(settings.target_axial_strain));

    CuboidResult out;
    out.width_x_m = std::move(cst.width_x_m);
    out.width_y_m = std::move(cst.width_y_m);
    out.sigma_x_pa = std::move(cst.sigma_x_pa);
    out.sigma_y_pa = std::move(cst.sigma_y_pa);
    // The servo's accuracy over the loading rows.
    std::size_t rows = 0;
    double deviation_sum = 0.0;
    for (std::size_t i = st.loading_start_sample; i < result.series.size(); ++i)
        for (const double s : {out.sigma_x_pa[i], out.sigma_y_pa[i]}) {
            const double d = std::abs(s - settings.confining_pressure_pa) / settings.confining_pressure_pa;
            out.servo_max_deviation = std::max(out.servo_max_deviation, d);
            deviation_sum += d;
            ++rows;
        }
    out.servo_mean_deviation = rows > 0 ? deviation_sum / static_cast<double>(rows) : 0.0;

    result.steps = st.steps;
    result.simulated_time_s = static_cast<double>(st.steps) * dt;
    result.wall_time_s = stepper.wall_time_s();
    out.triaxial = std::move(result);
    return out;
}

} // namespace wiredem::engine
