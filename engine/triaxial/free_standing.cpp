// The free-standing test driver; see free_standing.hpp.
#include "triaxial/free_standing.hpp"

#include "analysis/stress.hpp"
#include "energy.hpp"
#include "specimen/packing.hpp"
#include "specimen/preparation.hpp"
#include "timestep.hpp"
#include "triaxial/formwork.hpp"
#include "triaxial/loading.hpp"
#include "triaxial/pressure.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <span>

namespace wiredem::engine {
namespace {

bool is_plate(const World& w, std::size_t wall, double normal_z)
{
    return wall < w.walls.size() && w.walls[wall].shape == Wall::Shape::plane
        && w.walls[wall].normal.isApprox(Vec3(0.0, 0.0, normal_z));
}

std::optional<std::string> validate(const World& w, std::size_t top_plate_wall, const FreeStandingSettings& s)
{
    if (auto e = free_standing_settings_error(s)) return e->field + ": " + e->message;
    if (!is_plate(w, 0, 1.0)) return "wall 0 must be the bottom plate (a plane with its normal pointing up)";
    if (!is_plate(w, top_plate_wall, -1.0))
        return "wall " + std::to_string(top_plate_wall) + " must be the top plate (a plane with its normal pointing down)";
    if (w.of(BodyKind::grain).size() == 0) return "the world has no grains";
    if (w.of(BodyKind::membrane).size() == 0) return "the world has no membrane (the formwork to remove)";
    if (!(w.dt_s > 0.0)) return "the time step is not set";
    if (s.pull_out && w.of(BodyKind::wire).size() < 2) return "pull_out: the column has no wire to pull (fewer than two nodes)";
    return std::nullopt;
}

/// √(2⟨ρ²⟩) + ⟨r⟩ of the grains `in` selects (0 without any).
template <class In>
double equivalent_radius_m(const std::vector<Vec3>& x, const std::vector<double>& radius_m, In&& in, std::uint32_t& count)
{
    double rho2_sum = 0.0, r_sum = 0.0;
    count = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (!in(i)) continue;
        rho2_sum += x[i].x() * x[i].x() + x[i].y() * x[i].y();
        r_sum += radius_m[i];
        ++count;
    }
    if (count == 0) return 0.0;
    const double n = static_cast<double>(count);
    return std::sqrt(2.0 * rho2_sum / n) + r_sum / n;
}

bool standing(const Vec3& x, double escape_distance_m) { return std::hypot(x.x(), x.y()) <= escape_distance_m; }

/// The volume of a sphere of radius r below a plane a height h above its
/// lowest point, h in [0, 2r]: the cap π h² (3r − h)/3 (the sphere at h = 2r).
double cap_volume_m3(double r, double h) { return std::numbers::pi * h * h * (3.0 * r - h) / 3.0; }

} // namespace

std::optional<SettingsError> free_standing_settings_error(const FreeStandingSettings& s)
{
    const auto error = [](const char* field, std::string message) {
        return std::optional<SettingsError>(SettingsError{field, std::move(message)});
    };
    auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
    auto fraction = [](double v) { return v > 0.0 && v < 1.0; };
    if (!positive(s.removal_time_s)) return error("removal_time_s", format_number(s.removal_time_s) + " must be > 0");
    if (!positive(s.removal_distance_m))
        return error("removal_distance_m", format_number(s.removal_distance_m) + " must be > 0");
    if (!positive(s.escape_distance_m))
        return error("escape_distance_m", format_number(s.escape_distance_m) + " must be > 0");
    if (!positive(s.settle_kinetic_energy_per_grain_j))
        return error("settle_kinetic_energy_per_grain_j", format_number(s.settle_kinetic_energy_per_grain_j) + " must be > 0");
    if (!positive(s.max_settling_time_s))
        return error("max_settling_time_s", format_number(s.max_settling_time_s) + " must be > 0");
    if (!fraction(s.max_height_loss))
        return error("max_height_loss", format_number(s.max_height_loss) + " must lie in (0, 1)");
    if (!(s.bulk_fraction >= 0.5 && s.bulk_fraction <= 1.0))
        return error("bulk_fraction", format_number(s.bulk_fraction) + " must lie in [0.5, 1]");
    if (!(s.max_lost_fraction >= 0.0 && s.max_lost_fraction < 1.0))
        return error("max_lost_fraction", format_number(s.max_lost_fraction) + " must lie in [0, 1)");
    if (s.dead_load) {
        if (!positive(s.dead_load->force_n))
            return error("dead_load.force_n", format_number(s.dead_load->force_n) + " must be > 0");
        if (!(std::isfinite(s.dead_load->ramp_time_s) && s.dead_load->ramp_time_s >= 0.0))
            return error("dead_load.ramp_time_s", format_number(s.dead_load->ramp_time_s) + " must be ≥ 0");
        if (!positive(s.dead_load->hold_time_s))
            return error("dead_load.hold_time_s", format_number(s.dead_load->hold_time_s) + " must be > 0");
    }
    if (!positive(s.plate_speed_m_per_s))
        return error("plate_speed_m_per_s", format_number(s.plate_speed_m_per_s) + " must be > 0");
    if (!fraction(s.target_axial_strain))
        return error("target_axial_strain", format_number(s.target_axial_strain) + " must lie in (0, 1)");
    if (!(s.failure_drop > 0.0 && s.failure_drop <= 1.0))
        return error("failure_drop", format_number(s.failure_drop) + " must lie in (0, 1]");
    if (!positive(s.sample_interval_s))
        return error("sample_interval_s", format_number(s.sample_interval_s) + " must be > 0");
    for (double e : s.snapshot_strains)
        if (!std::isfinite(e)) return error("snapshot_strains", "every strain must be finite");
    if (s.pull_out) {
        if (s.dead_load)
            return error("pull_out", "a pull-out replaces the dead load and the compression: give one of pull_out and dead_load");
        if (auto e = pull_out_settings_error(*s.pull_out)) {
            e->field = "pull_out." + e->field;
            return e;
        }
    }
    return std::nullopt;
}

const char* to_string(FreeStandingPhase p) noexcept
{
    switch (p) {
    case FreeStandingPhase::removal: return "removal";
    case FreeStandingPhase::settling: return "settling";
    case FreeStandingPhase::dead_load: return "dead_load";
    case FreeStandingPhase::loading: return "loading";
    case FreeStandingPhase::pull_out: return "pull_out";
    }
    return "loading";
}

const char* to_string(FailureMode m) noexcept
{
    switch (m) {
    case FailureMode::wire_break: return "wire_break";
    case FailureMode::grains_spilling: return "grains_spilling";
    case FailureMode::bulging: return "bulging";
    case FailureMode::unresolved: return "unresolved";
    }
    return "unresolved";
}

FailureMode failure_mode(const FailureSigns& s, double max_lost_fraction, double max_radius_gain) noexcept
{
    if (s.wire_broke_at_peak) return FailureMode::wire_break;
    if (s.spilled_fraction > max_lost_fraction) return FailureMode::grains_spilling;
    if (s.bulge_m > max_radius_gain * s.radius_m) return FailureMode::bulging;
    return FailureMode::unresolved;
}

double column_bulge_m(const RadiusProfile& before, const RadiusProfile& after) noexcept
{
    if (before.radius_m.empty() || after.radius_m.empty()) return 0.0;
    return *std::max_element(after.radius_m.begin(), after.radius_m.end())
         - *std::max_element(before.radius_m.begin(), before.radius_m.end());
}

ColumnGrains column_grains(const World& w)
{
    ColumnGrains out;
    const TranslationalState& g = w.of(BodyKind::grain);
    const ClumpState& c = w.clumps;
    out.radius_m = grain_volumes(w).radius_m;
    out.position_m.reserve(out.radius_m.size());
    for (std::size_t i = 0; i < g.size(); ++i)
        if (!c.is_member(i)) out.position_m.push_back(g.x[0][i]);
    for (std::size_t k = 0; k < c.size(); ++k) out.position_m.push_back(c.x[0][k]);
    return out;
}

double bulk_height_m(const std::vector<Vec3>& position_m, const std::vector<double>& radius_m, double bottom_m,
    double escape_distance_m, double fraction)
{
    std::vector<std::pair<double, double>> grains; // (lowest point, radius) of the standing grains
    double total_m3 = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t i = 0; i < position_m.size(); ++i) {
        if (!standing(position_m[i], escape_distance_m)) continue;
        const double r = radius_m[i], base = position_m[i].z() - r;
        grains.emplace_back(base, r);
        total_m3 += cap_volume_m3(r, 2.0 * r);
        lo = std::min(lo, base);
        hi = std::max(hi, base + 2.0 * r);
    }
    if (grains.empty()) return 0.0;
    auto below_m3 = [&](double z) {
        double v = 0.0;
        for (const auto& [base, r] : grains) v += cap_volume_m3(r, std::clamp(z - base, 0.0, 2.0 * r));
        return v;
    };
    // V(z) rises continuously from 0 at lo to the total at hi: bisection to
    // the last bit of z (V(lo) < q V ≤ V(hi) throughout).
    const double target_m3 = fraction * total_m3;
    for (int k = 0; k < 200; ++k) {
        const double mid = 0.5 * (lo + hi);
        if (!(mid > lo && mid < hi)) break;
        (below_m3(mid) < target_m3 ? lo : hi) = mid;
    }
    return (hi - bottom_m) / fraction;
}

StandingColumn standing_column(const World& w, double escape_distance_m, double bulk_fraction)
{
    StandingColumn c;
    const double bottom_m = w.walls[0].point_m.z();
    const ColumnGrains g = column_grains(w);
    std::uint32_t count = 0;
    c.radius_m = equivalent_radius_m(g.position_m, g.radius_m, [&](std::size_t i) { return standing(g.position_m[i], escape_distance_m); }, count);
    c.grains = g.position_m.size();
    c.escaped_grains = c.grains - count;
    double all_m3 = 0.0, lost_m3 = 0.0;
    for (std::size_t i = 0; i < c.grains; ++i) {
        const double v = cap_volume_m3(g.radius_m[i], 2.0 * g.radius_m[i]);
        all_m3 += v;
        if (!standing(g.position_m[i], escape_distance_m)) lost_m3 += v;
    }
    c.lost_fraction = all_m3 > 0.0 ? lost_m3 / all_m3 : 0.0;
    c.bulk_height_m = bulk_height_m(g.position_m, g.radius_m, bottom_m, escape_distance_m, bulk_fraction);
    // The top is where a plate touches the column: every sphere (a clump's
    // too) and wire node.
    for (const TranslationalState* s : {&w.of(BodyKind::grain), &w.of(BodyKind::wire)})
        for (std::size_t i = 0; i < s->size(); ++i) {
            const Vec3& x = s->x[0][i];
            const double top = x.z() + s->radius_m[i] - bottom_m;
            if (standing(x, escape_distance_m)) c.top_m = std::max(c.top_m, top);
            if (top > c.highest_top_m) c.highest_top_m = top, c.highest_top_axis_distance_m = std::hypot(x.x(), x.y());
        }
    return c;
}

void judge_settled_column(SettlingReading& r, const StandingColumn& after, const FreeStandingSettings& s)
{
    r.height_m = after.top_m;
    r.bulk_height_m = after.bulk_height_m;
    r.radius_m = after.radius_m;
    r.grains = after.grains;
    r.escaped_grains = after.escaped_grains;
    r.lost_fraction = after.lost_fraction;
    r.height_loss = (r.height_before_m - r.height_m) / r.height_before_m;
    r.bulk_height_loss = (r.bulk_height_before_m - r.bulk_height_m) / r.bulk_height_before_m;
    // A wire standing above the grains keeps the top, not the bulk: the
    // verdict reads the bulk and the grains lost (docs/model.md, "What stands").
    r.stands = r.at_rest && r.bulk_height_loss <= s.max_height_loss && r.lost_fraction <= s.max_lost_fraction;
}

RadiusProfile radius_profile(const std::vector<Vec3>& position_m, const std::vector<double>& radius_m, double bottom_m,
    double escape_distance_m)
{
    RadiusProfile p;
    if (position_m.empty()) return p;
    double r_sum = 0.0, top = 0.0;
    for (std::size_t i = 0; i < position_m.size(); ++i) {
        r_sum += radius_m[i];
        if (standing(position_m[i], escape_distance_m)) top = std::max(top, position_m[i].z() - bottom_m);
    }
    const double slice_m = 2.0 * r_sum / static_cast<double>(position_m.size());
    const auto slices = static_cast<std::size_t>(std::floor(top / slice_m)) + 1;
    for (std::size_t k = 0; k < slices; ++k) {
        const double lo = bottom_m + static_cast<double>(k) * slice_m, hi = lo + slice_m;
        std::uint32_t count = 0;
        const double r = equivalent_radius_m(position_m, radius_m, [&](std::size_t i) {
            const double z = position_m[i].z();
            return z >= lo && z < hi && standing(position_m[i], escape_distance_m);
        }, count);
        if (count == 0) continue;
        p.height_m.push_back((static_cast<double>(k) + 0.5) * slice_m);
        p.radius_m.push_back(r);
        p.grains.push_back(count);
    }
    return p;
}

Deposit deposit(const std::vector<Vec3>& position_m, const std::vector<double>& radius_m, double bottom_m, double fraction)
{
    Deposit d;
    if (position_m.empty()) return d;
    std::vector<double> edge(position_m.size());
    for (std::size_t i = 0; i < position_m.size(); ++i) edge[i] = std::hypot(position_m[i].x(), position_m[i].y()) + radius_m[i];
    std::vector<double> sorted = edge;
    std::sort(sorted.begin(), sorted.end());
    // The ⌈f N⌉-th smallest edge: the smallest radius that holds f N of them.
    const auto n = static_cast<double>(sorted.size());
    const auto k = static_cast<std::size_t>(std::clamp(std::ceil(fraction * n), 1.0, n)) - 1;
    d.runout_radius_m = sorted[k];
    d.max_radius_m = sorted.back();
    for (std::size_t i = 0; i < position_m.size(); ++i)
        if (edge[i] <= d.runout_radius_m) d.height_m = std::max(d.height_m, position_m[i].z() + radius_m[i] - bottom_m);
    return d;
}

double axial_force_through_plane_n(const World& w, double z_m)
{
    auto above = [&](BodyRef b) { return w.of(b.kind()).x[0][b.index()].z() > z_m; };
    double up_n = 0.0;
    const ContactList& c = w.contacts;
    for (std::size_t p = 0; p < c.pair_count(); ++p) { // pairs: the force on `first`, −it on `second`
        if (!c.touching[p]) continue;
        const bool a = above(c.first[p]), b = above(c.second[p]);
        if (a == b) continue;
        up_n += a ? c.output[p].force_n.z() : -c.output[p].force_n.z();
    }
    const TranslationalState& n = w.of(BodyKind::wire);
    const WireForces& f = w.wire_forces;
    for (std::size_t s = 0; s + 1 < n.size(); ++s) { // segment s: its force on node s, −it on node s + 1
        const bool a = n.x[0][s].z() > z_m, b = n.x[0][s + 1].z() > z_m;
        if (a == b) continue;
        up_n += a ? f.segment_force_n[s].z() : -f.segment_force_n[s].z();
    }
    for (std::size_t j = 1; j + 1 < n.size(); ++j) { // the joint at node j on nodes j − 1, j, j + 1
        const bool side[3] = {n.x[0][j - 1].z() > z_m, n.x[0][j].z() > z_m, n.x[0][j + 1].z() > z_m};
        if (side[0] == side[1] && side[1] == side[2]) continue;
        for (int k = 0; k < 3; ++k)
            if (side[k]) up_n += f.bending_force_n[static_cast<std::size_t>(k)][j].z();
    }
    return up_n;
}

double column_weight_n(const World& w)
{
    double down_n = 0.0;
    for (std::size_t k = 0; k < body_kind_count; ++k) {
        if (!w.gravity_acts[k]) continue;
        const TranslationalState& b = w.bodies[k];
        for (std::size_t i = 0; i < b.size(); ++i)
            if (is_dynamic(b, i)) down_n -= b.mass_kg[i] * w.gravity_m_per_s2.z();
    }
    for (const auto& [body, force] : w.point_loads) down_n -= force.z();
    return down_n;
}

double longest_free_standing_time_s(const FreeStandingSettings& s, double height_m)
{
    double t = s.removal_time_s + s.max_settling_time_s
             + (s.pull_out ? s.pull_out->max_time_s : loading_time_s(s.target_axial_strain, height_m, s.plate_speed_m_per_s));
    if (s.dead_load) t += s.dead_load->ramp_time_s + s.dead_load->hold_time_s;
    return t;
}

std::uint64_t expected_free_standing_steps(const FreeStandingSettings& s, double height_m, double dt_s)
{
    return static_cast<std::uint64_t>(std::ceil(longest_free_standing_time_s(s, height_m) / dt_s));
}

Result<FreeStandingResult, std::string> run_free_standing(Simulation& sim, std::size_t top_plate_wall,
    const FreeStandingSettings& settings, const RunControl& control, FreeStandingContinuation continuation)
{
    const auto wall_start = std::chrono::steady_clock::now();
    World& w = sim.world;
    ThreadPool& pool = sim.pool();
    if (auto e = validate(w, top_plate_wall, settings)) return Err(*e);
    constexpr std::size_t bottom_plate_wall = 0;
    const TranslationalState& grains = w.of(BodyKind::grain);
    const auto plates_apart_m = [&] {
        return w.walls[top_plate_wall].point_m.z() - w.walls[bottom_plate_wall].point_m.z();
    };
    const double dt = w.dt_s;
    const bool continued = continuation.from.has_value();
    FreeStandingDriverState st = continued ? std::move(*continuation.from) : FreeStandingDriverState{};
    FreeStandingResult& result = st.result;
    const double removal_speed = settings.removal_distance_m / settings.removal_time_s;
    if (!continued) {
        // Formwork: what the column stands like before it goes.
        const StandingColumn before = standing_column(w, settings.escape_distance_m, settings.bulk_fraction);
        result.settling.height_before_m = before.top_m;
        result.settling.bulk_height_before_m = before.bulk_height_m;
        result.settling.radius_before_m = before.radius_m;
        const ColumnGrains g = column_grains(w);
        result.settling.profile_before
            = radius_profile(g.position_m, g.radius_m, w.walls[bottom_plate_wall].point_m.z(), settings.escape_distance_m);
        st.reference_height_m = before.top_m;
        st.reference_radius_m = before.radius_m;
        if (settings.real_weights)
            set_weights(w, settings.real_weights->density_scale, settings.real_weights->wire_mass_scale, 1.0);
        w.membrane.pressure_pa = 0.0;
        open_formwork(w, removal_speed);
        w.walls[top_plate_wall].velocity_m_per_s = Vec3(0.0, 0.0, removal_speed);
        result.time_step_s = dt;
        if (auto warning = sample_interval_warning(settings.sample_interval_s, dt))
            result.warnings.push_back("free-standing test: " + *warning);
    } else if (st.steps > std::numeric_limits<std::uint64_t>::max() / 2 || !(st.reference_height_m > 0.0)
               || !(st.reference_radius_m > 0.0)) {
        return Err(std::string("the test's saved state is inconsistent (steps or heights)"));
    }
    const StableStep crit = stable_time_step(w);
    if (dt > crit.critical_s)
        return Err("time step " + format_number(dt) + " s exceeds the stable limit " + format_number(crit.critical_s)
                   + " s set by the " + crit.limited_by);
    if (crit.overdamped()) return Err(overdamped_error(crit, w.contact.normal_damping_s));

    // Grains as grains: a clump's spheres have no mass of their own (the
    // clump has it) and it counts once in the mean radius and per grain.
    double column_mass_kg = 0.0;
    for (double m : grains.mass_kg) column_mass_kg += m;
    for (double m : w.clumps.mass_kg) column_mass_kg += m;
    const double grain_radius_m = mean_grain_radius_m(w);
    const double grain_density = w.materials[grains.material[0]].density_kg_per_m3;
    const double wire_mass_scale = settings.real_weights ? settings.real_weights->wire_mass_scale : 1.0;
    const double density_scale = settings.real_weights ? settings.real_weights->density_scale : 1.0;
    const auto steps_of = [&](double t_s) { return static_cast<std::uint64_t>(std::ceil(t_s / dt)); };
    const std::uint64_t sample_every = steps_per_sample(settings.sample_interval_s, dt);
    const auto check_every = static_cast<std::uint64_t>(std::max(1.0, std::round(1e-3 / dt)));
    const std::vector<double> plan = snapshot_plan(settings.target_axial_strain, settings.snapshot_strains);
    if (continued && st.next_snapshot > plan.size())
        return Err(std::string("the test's saved state is inconsistent (snapshot plan)"));
    const std::uint64_t expected = expected_free_standing_steps(settings, st.reference_height_m, dt);
    // The breaks the World had before the test (a continued test has recorded the rest).
    if (result.wire_breaks.size() > w.wire_breaks.size())
        return Err(std::string("the test's saved state is inconsistent (more wire breaks than the World has)"));
    const std::size_t breaks_before_test = w.wire_breaks.size() - result.wire_breaks.size();
    const double bottom_m = w.walls[bottom_plate_wall].point_m.z();

    // The settled column, where the pull-out counts wire as still in it.
    auto column_region = [&] { return ColumnRegion{bottom_m, st.reference_height_m, settings.escape_distance_m}; };
    // Sampling: the triaxial row, with the free column's radius and σ₁ on
    // its settled cross-section.
    auto sample = [&] {
        TriaxialSample s = measure_triaxial_sample(w, pool, top_plate_wall, bottom_plate_wall, st.reference_height_m);
        s.time_s = static_cast<double>(st.steps) * dt;
        const StandingColumn column = standing_column(w, settings.escape_distance_m, settings.bulk_fraction);
        s.column_radius_m = column.radius_m;
        s.sigma1_pa = analysis::axial_stress_pa(s.top_plate_force_n, st.reference_radius_m);
        s.deviatoric_stress_pa = analysis::deviatoric_stress_pa(s.sigma1_pa, s.sigma3_effective_pa);
        s.stress_ratio = analysis::stress_ratio(s.sigma1_pa, s.sigma3_effective_pa);
        s.volume_m3 = analysis::cylinder_volume_m3(s.column_radius_m, s.height_m);
        // The membrane's springs are no part of the column (stretched as it
        // opens, then gone): the stored energy is the contacts' and the wire's.
        const ElasticEnergy stored = elastic_energy(w, pool);
        s.elastic_energy_j = stored.contacts_j + stored.wire_j;
        if (st.phase == FreeStandingPhase::loading) // ε̇ = v/h₀, with the column's own σ₁ as the pressure
            s.inertial_number = analysis::inertial_number(
                settings.plate_speed_m_per_s / st.reference_height_m, grain_radius_m, grain_density, s.sigma1_pa);
        result.series.push_back(s);
        result.series.phase.back() = static_cast<std::uint8_t>(st.phase);
        st.last_sample_step = st.steps;
        if (st.phase == FreeStandingPhase::pull_out && result.pull_out) { // the pull's row beside it
            PullOutReading& r = *result.pull_out;
            const Vec3 d = settings.pull_out->direction.normalized();
            const double steps = static_cast<double>(std::max<std::uint64_t>(st.pull_steps_summed, 1));
            const double force_n = st.pull_force_sum_n / steps;
            const double pulled_m = (w.of(BodyKind::wire).x[0][r.pulled_node] - st.pull_start_m).dot(d);
            PullOutSeries& ps = r.series;
            ps.time_s.push_back(s.time_s);
            ps.pulled_length_m.push_back(pulled_m);
            ps.pull_force_n.push_back(force_n);
            ps.end_tension_n.push_back(st.end_tension_sum_n / steps);
            st.pull_force_sum_n = st.end_tension_sum_n = 0.0;
            st.pull_steps_summed = 0;
            if (force_n > r.peak_pull_force_n) {
                r.peak_pull_force_n = force_n;
                r.pulled_length_at_peak_m = pulled_m;
            }
            ps.wire_in_column_m.push_back(wire_in_region_m(w, column_region()));
            ps.grains_in_column.push_back(static_cast<double>(column.grains - column.escaped_grains));
        }
    };
    auto sample_unless_taken = [&] {
        if (st.last_sample_step != st.steps) sample();
    };

    ColumnTestStepper<FreeStandingDriverState> stepper(
        sim, control, continuation.between_steps, st, "the free-standing test", wall_start);
    auto progress = [&] { return std::pair<std::uint64_t, std::uint64_t>{st.steps, std::max(expected, st.steps)}; };
    auto advance = [&](auto&& prescribe) -> std::optional<std::string> {
        if (auto e = stepper.step(prescribe, progress)) return e;
        if (st.phase == FreeStandingPhase::pull_out) { // the pull of every step goes into the row's mean
            const PullForces f = pull_forces(w, settings.pull_out->end, settings.pull_out->direction.normalized());
            st.pull_force_sum_n += f.pull_force_n;
            st.end_tension_sum_n += f.end_tension_along_n;
            ++st.pull_steps_summed;
        }
        if (w.wire_breaks.size() > breaks_before_test + result.wire_breaks.size())
            record_wire_breaks(w, breaks_before_test, static_cast<double>(st.steps) * dt,
                analysis::axial_strain(st.reference_height_m, plates_apart_m()), result.wire_breaks);
        if ((st.steps - 1) % sample_every == 0) sample();
        return std::nullopt;
    };
    auto nothing = [] {};
    auto place_plate_on_column = [&] {
        Wall& plate = w.walls[top_plate_wall];
        plate.point_m.z() = bottom_m + st.reference_height_m;
        plate.velocity_m_per_s.setZero();
        invalidate_neighbours(w);
    };

    // 1. Removal: the membrane opens and the plate rises at removal_speed.
    if (st.phase == FreeStandingPhase::removal) {
        const std::uint64_t removal_steps = steps_of(settings.removal_time_s);
        while (st.steps - st.phase_start_step < removal_steps) {
            if (auto e = advance(nothing)) return Err(*e);
            result.settling.max_removal_kinetic_energy_j
                = std::max(result.settling.max_removal_kinetic_energy_j, kinetic_energy_j(w, pool));
        }
        sample_unless_taken();
        close_formwork(w);
        w.walls[top_plate_wall].velocity_m_per_s.setZero();
        st.window_kinetic_energy_j = kinetic_energy_j(w, pool);
        st.phase = FreeStandingPhase::settling;
        st.phase_start_step = st.steps;
    }

    // 2. Settling under the column's own weight until at rest (the
    // preparation's criterion, looked at every millisecond) or the limit.
    if (st.phase == FreeStandingPhase::settling) {
        // The bottom plate's force is averaged over each check interval τ:
        // over it, mean F − W = ΔP/τ (the column's vertical momentum), and
        // |P| ≤ √(2 M K) bounds the difference (free_standing.hpp).
        const std::uint64_t max_steps = steps_of(settings.max_settling_time_s);
        SettlingReading& r = result.settling;
        r.weight_n = column_weight_n(w);
        double moving_mass_kg = 0.0;
        for (const TranslationalState& b : w.bodies)
            for (std::size_t i = 0; i < b.size(); ++i)
                if (is_dynamic(b, i)) moving_mass_kg += b.mass_kg[i];
        bool at_rest = false;
        while (st.steps - st.phase_start_step < max_steps) {
            if (auto e = advance(nothing)) return Err(*e);
            st.window_force_n += plate_compression_n(w, bottom_plate_wall);
            if ((st.steps - st.phase_start_step) % check_every != 0) continue;
            const double ke = kinetic_energy_j(w, pool);
            r.base_force_n = st.window_force_n / static_cast<double>(check_every);
            r.base_force_tolerance_n = (std::sqrt(2.0 * moving_mass_kg * st.window_kinetic_energy_j)
                                           + std::sqrt(2.0 * moving_mass_kg * ke))
                                     / (static_cast<double>(check_every) * dt);
            st.window_force_n = 0.0;
            st.window_kinetic_energy_j = ke;
            // The standing column's grains only: one that left it is lost
            // (lost_fraction), and a sphere without rolling resistance rolls
            // on the plate for ever, which would keep a column that stands
            // from ever being at rest.
            const SettlingEnergy column = settling_energy_of(w, wire_mass_scale,
                [&settings](const Vec3& x) { return standing(x, settings.escape_distance_m); });
            if (column.grains > 0
                && column.energy_j / static_cast<double>(column.grains)
                       < settings.settle_kinetic_energy_per_grain_j * density_scale) {
                at_rest = true;
                break;
            }
        }
        sample_unless_taken();
        r.at_rest = at_rest;
        r.time_to_rest_s = static_cast<double>(st.steps - st.phase_start_step) * dt;
        const StandingColumn after = standing_column(w, settings.escape_distance_m, settings.bulk_fraction);
        judge_settled_column(r, after, settings);
        const ColumnGrains g = column_grains(w);
        r.profile = radius_profile(g.position_m, g.radius_m, bottom_m, settings.escape_distance_m);
        if (!at_rest)
            result.warnings.push_back("the free column was not at rest after " + format_number(settings.max_settling_time_s)
                                      + " s of settling; lengthen max_settling_time_s");
        if (!(after.top_m > 0.0 && after.radius_m > 0.0))
            return Err(std::string("no grain is left standing within escape_distance_m of the axis"));
        st.reference_height_m = after.top_m;
        st.reference_radius_m = after.radius_m;
        // The top plate is a plane over the whole bottom plate: set on the
        // column, it would cut into a grain or wire node that left the column
        // and lies higher. It is set on the highest of them then, the
        // compression's strain measured from there, and the result says so.
        if (!settings.pull_out && after.highest_top_m > after.top_m) {
            st.reference_height_m = after.highest_top_m;
            result.warnings.push_back("the top plate was set at " + format_number(1e3 * after.highest_top_m)
                + " mm, on a body that left the column (" + format_number(1e3 * after.highest_top_axis_distance_m)
                + " mm from the axis), " + format_number(1e3 * (after.highest_top_m - after.top_m))
                + " mm above the standing column's top: the plate, a plane, presses what lies beyond escape_distance_m "
                  "as well as the column, and the unconfined compression does not measure the column alone");
        }
        if (!settings.pull_out) place_plate_on_column(); // a pull-out leaves the plate above the column
        st.phase = settings.pull_out ? FreeStandingPhase::pull_out
                 : settings.dead_load ? FreeStandingPhase::dead_load : FreeStandingPhase::loading;
        st.phase_start_step = st.steps;
    }

    const double max_plate_speed = max_piston_speed_factor * settings.plate_speed_m_per_s;
    auto strain_now = [&] { return analysis::axial_strain(st.reference_height_m, plates_apart_m()); };

    // 3. Dead load: the plate is a piston of the column's mass pushed by F(t).
    if (st.phase == FreeStandingPhase::dead_load) {
        const DeadLoad& d = *settings.dead_load;
        const std::uint64_t ramp_steps = steps_of(d.ramp_time_s), hold_steps = steps_of(d.hold_time_s);
        auto push = [&] {
            const double t = static_cast<double>(st.steps + 1 - st.phase_start_step) * dt;
            double& v = w.walls[top_plate_wall].velocity_m_per_s.z();
            v = piston_velocity_m_per_s(v, ramped_pressure_pa(d.force_n, t, d.ramp_time_s),
                plate_compression_n(w, top_plate_wall), dt, column_mass_kg, max_plate_speed);
        };
        if (!result.dead_load) { // the reading grows in the result, which a checkpoint saves
            result.dead_load = DeadLoadReading{};
            result.dead_load->force_n = d.force_n;
            result.dead_load->stress_pa = analysis::axial_stress_pa(d.force_n, st.reference_radius_m);
        }
        DeadLoadReading& r = *result.dead_load;
        bool collapsed = false;
        while (st.steps - st.phase_start_step < ramp_steps + hold_steps) {
            if (auto e = advance(push)) return Err(*e);
            if (st.steps - st.phase_start_step == ramp_steps) r.strain_at_load = strain_now();
            if (strain_now() >= settings.target_axial_strain) {
                collapsed = true;
                break;
            }
        }
        sample_unless_taken();
        if (ramp_steps == 0) r.strain_at_load = 0.0;
        r.strain_at_end = strain_now();
        r.creep_strain = r.strain_at_end - r.strain_at_load;
        r.holds = !collapsed;
        st.phase = FreeStandingPhase::loading;
        st.phase_start_step = st.steps;
    }

    // 4'. Pulling the wire out (instead of the compression): one end node
    // driven at v d̂ until the pulled length, the pulled piece's exit from the
    // settled column, or max_time_s.
    if (st.phase == FreeStandingPhase::pull_out) {
        const PullOutSettings& p = *settings.pull_out;
        const Vec3 d = p.direction.normalized();
        if (!result.pull_out) {
            PullOutReading r;
            r.pulled_node = pulled_node(w, p.end);
            r.wire_in_column_before_m = wire_in_region_m(w, column_region());
            st.pull_start_m = w.of(BodyKind::wire).x[0][r.pulled_node];
            result.pull_out = std::move(r);
            result.loading_start_sample = result.series.size();
            // The plate rises with the pulled end, never onto the wire.
            w.walls[top_plate_wall].velocity_m_per_s = Vec3(0.0, 0.0, std::max(0.0, p.speed_m_per_s * d.z()));
        }
        PullOutReading& r = *result.pull_out;
        const std::uint64_t max_steps = steps_of(p.max_time_s);
        auto pulled_length_m = [&] { return (w.of(BodyKind::wire).x[0][r.pulled_node] - st.pull_start_m).dot(d); };
        r.end = PullOutEnd::time;
        // The drive's speed is set before each step of the ramp (and the
        // first): a kinematic node keeps it afterwards.
        auto drive = [&] {
            const double t = static_cast<double>(st.steps + 1 - st.phase_start_step) * dt;
            if (st.steps == st.phase_start_step || t < p.ramp_time_s + dt) drive_pulled_node(w, p, t);
        };
        while (st.steps - st.phase_start_step < max_steps) {
            if (auto e = advance(drive)) return Err(*e);
            if (p.length_m && pulled_length_m() >= *p.length_m) {
                r.end = PullOutEnd::length;
                break;
            }
            if (!p.length_m && (st.steps - st.phase_start_step) % check_every == 0
                && !(wire_in_region_m(w, column_region(), r.pulled_node) > 0.0)) {
                r.end = PullOutEnd::wire_out;
                break;
            }
            if (control.after_step && !control.after_step(w, StepReport{})) {
                r.end = PullOutEnd::host;
                break;
            }
        }
        sample_unless_taken();
        w.walls[top_plate_wall].velocity_m_per_s.setZero();
        set_velocity(w, {BodyKind::wire, r.pulled_node}, Vec3::Zero());
        r.pulled_length_m = pulled_length_m();
        r.wire_in_column_m = wire_in_region_m(w, column_region());
        const StandingColumn column = standing_column(w, settings.escape_distance_m, settings.bulk_fraction);
        r.grains_in_column = column.grains - column.escaped_grains;
        const double pull_began_s = static_cast<double>(st.phase_start_step) * dt;
        r.wire_broke = std::any_of(result.wire_breaks.begin(), result.wire_breaks.end(),
            [&](const TestWireBreak& b) { return b.test_time_s > pull_began_s; });
        double wire_mass_kg = 0.0;
        for (double m : w.of(BodyKind::wire).mass_kg) wire_mass_kg += m;
        r.ramp_inertia_n = p.ramp_time_s > 0.0 ? wire_mass_kg * p.speed_m_per_s * std::numbers::pi / (2.0 * p.ramp_time_s)
                                               : std::numeric_limits<double>::infinity();
        if (r.pulled_length_at_peak_m <= 0.5 * p.speed_m_per_s * p.ramp_time_s + 1e-12
            && !(r.ramp_inertia_n < 0.1 * r.peak_pull_force_n))
            result.warnings.push_back("pull-out: the peak pull force " + format_number(r.peak_pull_force_n)
                                      + " N came during the speed ramp, where accelerating the wire takes up to "
                                      + format_number(r.ramp_inertia_n)
                                      + " N (its masses as scaled): lengthen pull_out_ramp_time_s or lower the wire's mass scaling");
        if (r.end == PullOutEnd::time)
            result.warnings.push_back("pull-out: " + std::string(p.length_m ? "the pulled length" : "the wire's exit from the column")
                                      + " was not reached in max_time_s = " + format_number(p.max_time_s) + " s");
        if (r.end == PullOutEnd::host)
            result.warnings.push_back("pull-out: stopped by the host after " + format_number(r.pulled_length_m) + " m");
        result.steps = st.steps;
        result.simulated_time_s = static_cast<double>(st.steps) * dt;
        result.wall_time_s = stepper.wall_time_s();
        return std::move(result);
    }

    // 4. Unconfined compression at constant plate speed, from h₀ of the
    // settled column, to failure or the target strain.
    const analysis::CurveTolerances tol;
    auto track_row = [&] { // a row of the compression was just taken: the largest σ₁ and its snapshot
        const double s1 = result.series.sigma1_pa.back();
        if (!(s1 > st.max_sigma1_pa)) return;
        st.max_sigma1_pa = s1;
        TriaxialSnapshot snap = take_triaxial_snapshot(w);
        snap.axial_strain = snap.requested_axial_strain = result.series.axial_strain.back();
        snap.time_s = result.series.time_s.back();
        result.peak_snapshot = std::move(snap);
        const ColumnGrains g = column_grains(w); // the snapshot's are spheres
        st.profile_at_max_sigma1 = radius_profile(g.position_m, g.radius_m, bottom_m, settings.escape_distance_m);
    };
    if (!st.loading_begun) {
        // Straight from the settling the plate was just set on the column: its
        // last row has the plate where the removal left it (above the column,
        // ε < 0) and the contact forces of that step. One step with the plate
        // at rest gives the first row its place and its forces. (After a dead
        // load the plate is on the column already.) A checkpoint is taken
        // before a step: continued from the one before this step, the test
        // takes it (no step of the phase yet); from any later one, not.
        if (!result.dead_load && st.steps == st.phase_start_step)
            if (auto e = advance(nothing)) return Err(*e);
        st.loading_begun = true;
        if (st.last_sample_step == st.steps) { // this step's row belongs to the loading
            result.series.phase.back() = static_cast<std::uint8_t>(FreeStandingPhase::loading);
            result.series.inertial_number.back() = analysis::inertial_number(settings.plate_speed_m_per_s
                / st.reference_height_m, grain_radius_m, grain_density, result.series.sigma1_pa.back());
        } else {
            sample();
        }
        result.loading_start_sample = result.series.size() - 1;
        track_row();
        take_due_snapshots(w, plan, st.next_snapshot, strain_now(), static_cast<double>(st.steps) * dt, result.snapshots);
        w.walls[top_plate_wall].velocity_m_per_s = Vec3(0.0, 0.0, -settings.plate_speed_m_per_s);
    }
    const std::size_t from = result.loading_start_sample;
    auto strain_after_step = [&] {
        const double strain = strain_now();
        take_due_snapshots(w, plan, st.next_snapshot, strain, static_cast<double>(st.steps) * dt, result.snapshots);
        if (st.last_sample_step == st.steps) track_row();
        return strain;
    };
    // Failure: σ₁ averaged over the rows of the last smoothing_strain has
    // stayed below (1 − failure_drop) of the largest such average for the
    // last end_window_strain of strain (looked at on rows; a dip of the
    // noisy curve, or the plate's first touch, is not a failure).
    auto failed = [&](double strain) {
        if (st.last_sample_step != st.steps) return false;
        const TriaxialSeries& s = result.series;
        const std::size_t last = s.size() - 1;
        double sum = 0.0;
        std::size_t n = 0;
        for (std::size_t i = last + 1; i-- > from && s.axial_strain[i] >= s.axial_strain[last] - tol.smoothing_strain; ++n)
            sum += s.sigma1_pa[i];
        const double mean = sum / static_cast<double>(n);
        st.max_window_sigma1_pa = std::max(st.max_window_sigma1_pa, mean);
        if (!(mean < (1.0 - settings.failure_drop) * st.max_window_sigma1_pa)) {
            st.below_since_strain = std::numeric_limits<double>::quiet_NaN();
            return false;
        }
        if (std::isnan(st.below_since_strain)) st.below_since_strain = strain;
        return strain - st.below_since_strain >= tol.end_window_strain;
    };
    const auto end = load_to_target(
        w, control, settings.target_axial_strain, [&] { return advance(nothing); }, strain_after_step, failed);
    if (!end.ok()) return Err(end.error());
    w.walls[top_plate_wall].velocity_m_per_s.setZero();
    if (st.last_sample_step != st.steps) {
        sample();
        track_row();
    }

    // Reading the compression (analysis/strength.hpp's rules on σ₁).
    const TriaxialSeries& ts = result.series;
    const auto at = static_cast<std::ptrdiff_t>(from);
    const std::span<const double> strain(ts.axial_strain.begin() + at, ts.axial_strain.end());
    const std::span<const double> s1(ts.sigma1_pa.begin() + at, ts.sigma1_pa.end());
    auto reading = analysis::read_curve(strain, analysis::smooth_over_strain(strain, s1, tol.smoothing_strain), tol);
    if (reading.ok()) {
        CompressionReading c;
        c.strength = reading.value();
        c.strength.index += from;
        c.strength_axial_strain = ts.axial_strain[c.strength.index];
        const auto max = std::max_element(s1.begin(), s1.end());
        c.max_sigma1_pa = *max;
        c.max_sigma1_sample = from + static_cast<std::size_t>(max - s1.begin());
        c.failed = end.value() == LoadingEnd::done;
        if (result.peak_snapshot) {
            const TriaxialSnapshot& p = *result.peak_snapshot;
            c.profile_at_peak = st.profile_at_max_sigma1;
            c.wire_strain_at_peak = p.wire_segment_strain;
            for (double e : p.wire_segment_strain)
                c.wire_tension_at_peak_n.push_back(w.wire.axial_stiffness_n_per_m * e * w.wire.segment_length_m);
        }
        const ColumnGrains g = column_grains(w);
        c.profile_at_end = radius_profile(g.position_m, g.radius_m, bottom_m, settings.escape_distance_m);
        // How it failed: the wire at the peak, the grains lost and the
        // widest slice's gain since the column settled.
        FailureSigns signs;
        signs.wire_broke_at_peak = peak_failure(ts, c.max_sigma1_sample, result.wire_breaks) == PeakFailure::wire;
        signs.spilled_fraction = standing_column(w, settings.escape_distance_m, settings.bulk_fraction).lost_fraction
                               - result.settling.lost_fraction;
        signs.bulge_m = column_bulge_m(result.settling.profile, c.profile_at_end);
        signs.radius_m = st.reference_radius_m;
        c.spilled_fraction = signs.spilled_fraction;
        c.bulge_m = signs.bulge_m;
        c.failure_mode = failure_mode(signs, settings.max_lost_fraction, settings.max_height_loss);
        result.compression = std::move(c);
    } else {
        result.warnings.push_back("unconfined compression: no strength read: " + reading.error());
    }
    // Quasi-static verdict over the rows that bear load: from the first
    // compression row at bearing_fraction of the largest σ₁ on (before, the
    // plate has no stress scale: I = ε̇ d √(ρ/σ₁) is unbounded at σ₁ → 0).
    std::size_t bearing = from;
    while (bearing + 1 < ts.size() && !(ts.sigma1_pa[bearing] >= bearing_fraction * st.max_sigma1_pa)) ++bearing;
    result.verdict = quasi_static_verdict(ts, bearing);
    if (!result.verdict.quasi_static) {
        result.verdict.warning = "the unconfined compression was not quasi-static: " + result.verdict.warning
                               + "; lower the plate speed or the density scaling";
        result.warnings.push_back(result.verdict.warning);
    }
    if (end.value() == LoadingEnd::host)
        result.warnings.push_back("stopped by the host at axial strain " + format_number(ts.axial_strain.back())
                                  + " before the target " + format_number(settings.target_axial_strain));
    result.steps = st.steps;
    result.simulated_time_s = static_cast<double>(st.steps) * dt;
    result.wall_time_s = stepper.wall_time_s();
    return std::move(result);
}

} // namespace wiredem::engine
