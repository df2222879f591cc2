#include "specimen/preparation.hpp"

#include "core/result.hpp"
#include "scene.hpp"
#include "timestep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

namespace wiredem::engine {
namespace {

constexpr double assumed_packing_fraction = 0.58; // for the fill-height estimate while pouring

/// The nozzle: walks the pattern at constant path speed, rises with the pile,
/// and drops a wire node every segment length.
class Nozzle {
public:
    Nozzle(const PreparationSpec& spec, double start_z_m)
        : path_(spec.pattern, 2.5 * spec.wire.radius_m), spec_(spec), z_m_(start_z_m)
    {
    }

    /// Advances by δt towards `target_z_m` (at most v_z^w) and lays a node
    /// each time the nozzle is a segment length from the previous one. The
    /// node is born at rest: the nozzle feeds wire backwards at its own speed,
    /// so laid wire does not move over the ground (docs/model.md: a node born
    /// with the nozzle's velocity drags the chain's free end along the path,
    /// or upwards, until the chain runs into itself).
    void advance(World& w, double dt, double target_z_m)
    {
        z_m_ += std::clamp(target_z_m - z_m_, 0.0, spec_.pattern.rise_speed_m_per_s * dt);
        s_m_ += path_.speed_m_per_s() * dt;
        // A node each time the nozzle has travelled one segment length along
        // its path (so the wire is laid at the path speed ω R_a), placed one
        // segment length from the wire's current end towards the nozzle: the
        // new segment is born unstrained even when the laid wire has moved
        // (it springs back towards straight: its bending springs have no rest
        // angle, the model spec §3).
        const Vec3 here = path_.at(s_m_) + Vec3(0, 0, z_m_);
        const auto& x = w.of(BodyKind::wire).x[0];
        if (x.empty()) {
            lay(w, here);
            s_last_node_m_ = s_m_;
        } else if (s_m_ - s_last_node_m_ >= spec_.wire.segment_length_m) {
            const Vec3 reach = here - x.back();
            const double len = reach.norm();
            lay(w, len > 0.0 ? Vec3(x.back() + spec_.wire.segment_length_m / len * reach)
                             : Vec3(here + Vec3(0, 0, spec_.wire.segment_length_m)));
            s_last_node_m_ += spec_.wire.segment_length_m;
        }
    }
    /// Lets go of the wire's end (when the laying is over): both ends free.
    static void release_end(World& w)
    {
        TranslationalState& wire = w.of(BodyKind::wire);
        if (wire.size() > 0) wire.inv_mass_per_kg.back() = 1.0 / wire.mass_kg.back();
    }
    [[nodiscard]] double z_m() const { return z_m_; }
    [[nodiscard]] Vec3 position() const { return path_.at(s_m_) + Vec3(0, 0, z_m_); }

private:
    /// Appends a node and holds it where it was laid until the next one: the
    /// wire's end is inside the nozzle, so it cannot whip. A wire laid along
    /// a curve stores ½ k_rot ζ² per joint (straight rest shape, the model
    /// spec §3); with a free end that energy is released at the end of the
    /// chain as a whip of tens of m/s. Held, each joint can only relax
    /// against its neighbours and the grains, short-wave motion that the
    /// wire's own damping absorbs.
    static void lay(World& w, const Vec3& at)
    {
        release_end(w);
        const std::uint32_t id = append_wire_node(w, at);
        w.of(BodyKind::wire).inv_mass_per_kg[id] = 0.0;
    }

    NozzlePath path_;
    const PreparationSpec& spec_;
    double z_m_;
    double s_m_ = 0.0;
    double s_last_node_m_ = 0.0;
};

/// Highest top (z + r) of the bodies within `reach` of the vertical line
/// through `at` whose bottom is below `at` (what the nozzle would run into;
/// grains falling from above do not count). The newest `own_nodes` wire
/// nodes are the nozzle's own output, still at its height: they do not
/// count, or the nozzle would climb over the wire it is laying.
double local_top_m(const World& w, const Vec3& at, double reach, std::size_t own_nodes)
{
    double top = 0.0;
    for (int k = 0; k < 2; ++k) { // grains and wire
        const TranslationalState& b = w.bodies[k];
        const std::size_t n = k == 1 ? b.size() - std::min(b.size(), own_nodes) : b.size();
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3& x = b.x[0][i];
            if (x.z() + b.radius_m[i] <= top || x.z() - b.radius_m[i] > at.z()) continue;
            if (std::hypot(x.x() - at.x(), x.y() - at.y()) < reach + b.radius_m[i]) top = x.z() + b.radius_m[i];
        }
    }
    return top;
}

/// Kinetic energy of grains (translation and rotation) and wire nodes, the
/// nodes' masses divided by their extra scale M [J]. Serial, in id order.
double settling_energy_j(const World& w, double node_mass_scale)
{
    double e = 0.0;
    const TranslationalState& g = w.of(BodyKind::grain);
    const double inv_dt2 = 1.0 / (w.dt_s * w.dt_s);
    for (std::size_t i = 0; i < g.size(); ++i) {
        e += 0.5 * g.mass_kg[i] * g.x[1][i].squaredNorm() * inv_dt2;
        const Vec3 omega = angular_velocity_rad_per_s(w, static_cast<std::uint32_t>(i));
        const double inv_i = w.grain_rotation.inv_inertia_per_kg_m2[i];
        if (inv_i > 0.0) e += 0.5 * omega.squaredNorm() / inv_i;
    }
    const TranslationalState& n = w.of(BodyKind::wire);
    for (std::size_t i = 0; i < n.size(); ++i)
        if (n.inv_mass_per_kg[i] != 0.0) e += 0.5 * n.mass_kg[i] / node_mass_scale * n.x[1][i].squaredNorm() * inv_dt2;
    return e;
}

} // namespace

void set_weights(World& w, double density_scale, double node_mass_scale, double weight_factor)
{
    const Vec3 g(0.0, 0.0, -standard_gravity_m_per_s2);
    w.gravity_m_per_s2 = g * (weight_factor / density_scale);
    w.gravity_acts[static_cast<int>(BodyKind::wire)] = false;
    const TranslationalState& wire = w.of(BodyKind::wire);
    w.point_loads.clear();
    const double per_mass = weight_factor / (density_scale * node_mass_scale);
    for (std::uint32_t i = 0; i < wire.size(); ++i)
        w.point_loads.emplace_back(BodyRef(BodyKind::wire, i), wire.mass_kg[i] * per_mass * g);
}

Result<PreparationReport, std::string> prepare_specimen(Simulation& sim, const PreparationSpec& spec, const RunControl& control)
{
    const auto wall_start = std::chrono::steady_clock::now();
    const double R = spec.membrane_radius_m;
    const double r_max = spec.grain_radius_m * (1.0 + spec.grain_radius_spread);
    const double r_m = spec.membrane.contact_radius_m;
    const bool with_wire = spec.pattern.kind != PatternKind::none;
    if (with_wire && pattern_reach_m(spec.pattern) + spec.wire.radius_m + spec.clearance_m >= R - r_m)
        return Err(std::string("wire pattern reaches ") + std::to_string(pattern_reach_m(spec.pattern) * 1e3)
                   + " mm from the axis; with r_w and the clearance it must stay inside the membrane radius "
                   + std::to_string(R * 1e3) + " mm");
    const double grain_volume_est = static_cast<double>(spec.grain_count) * 4.0 / 3.0 * std::numbers::pi
                                  * std::pow(spec.grain_radius_m, 3) * (1.0 + spec.grain_radius_spread * spec.grain_radius_spread);
    const double fill_height = grain_volume_est / (assumed_packing_fraction * std::numbers::pi * R * R);
    if (fill_height + 8.0 * r_max > spec.membrane_height_m)
        return Err(std::string("the grains fill about ") + std::to_string(fill_height * 1e3)
                   + " mm; the membrane must be taller than that plus room for pouring ("
                   + std::to_string((fill_height + 8.0 * r_max) * 1e3) + " mm)");

    World& w = sim.world;
    w = World{};
    w.integrator = spec.integrator;
    w.contact = spec.contact;
    Material grain = spec.grain;
    grain.density_kg_per_m3 *= spec.density_scale;
    const std::uint8_t grain_mat = add_material(w, grain);
    const std::uint8_t plate_mat = add_material(w, spec.plate);
    add_wall(w, make_plate(0.0, +1.0, plate_mat));
    WireSpec wire = spec.wire;
    wire.density_scale = spec.density_scale * spec.node_mass_scale;
    configure_wire(w, wire);
    MembraneSpec membrane = spec.membrane;
    membrane.radius_m = R;
    membrane.height_m = spec.membrane_height_m;
    membrane.base_z_m = 0.0;
    membrane.density_scale = spec.density_scale; // the wire alone takes node_mass_scale
    build_membrane(w, membrane);
    set_membrane_rigid(w, true);
    const std::size_t mould_wall = add_wall(w, make_cylinder(R + r_m, plate_mat));
    // While the mould holds the wire, the wire does not touch the rigid
    // membrane: a node pressed into a hole of the mesh against the mould was
    // squeezed from four sides (overlaps far beyond the time step's reference,
    // measured: examples/small.json blew up).
    const bool wire_touches_membrane = w.kinds_interact[1][2];
    w.kinds_interact[1][2] = w.kinds_interact[2][1] = false;
    // Weights scaled like the masses while pouring (see preparation.hpp).
    set_weights(w, spec.density_scale, spec.node_mass_scale, spec.density_scale);

    // The time step must hold for the wire and the grains before they exist:
    // probe with one of each.
    {
        World probe = w;
        add_grain(probe, Vec3(0, 0, 1), spec.grain_radius_m * (1.0 - spec.grain_radius_spread), grain_mat);
        if (with_wire) {
            append_wire_node(probe, Vec3(0, 0, 2));
            append_wire_node(probe, Vec3(0, 0, 2 + spec.wire.segment_length_m));
        }
        // Fastest impact: entering the zone at the pour speed, then falling
        // through the zone and the gap above the pile (≤ 12 r_max).
        const double impact = spec.pour_speed_m_per_s + std::sqrt(2.0 * w.gravity_m_per_s2.norm() * 12.0 * r_max);
        w.dt_s = spec.time_step_s > 0.0 ? spec.time_step_s
                                        : auto_time_step_fraction * critical_time_step(probe, impact).critical_s;
    }
    const double dt = w.dt_s;

    const double pour_time = fill_height / spec.fill_rate_m_per_s;
    const double grains_per_s = static_cast<double>(spec.grain_count) / pour_time;
    const double zone_height = 4.0 * r_max;
    const double batch_interval = zone_height / spec.pour_speed_m_per_s;
    const double pour_radius = R - r_m - r_max - 0.05 * r_max; // grain centres inside the membrane spheres
    SplitMix64 rng(spec.seed);
    Nozzle nozzle(spec, spec.wire.radius_m + 0.1 * spec.wire.radius_m);
    double owed = 0.0;          // grains due but not yet placed
    double next_batch = 0.0;
    double nozzle_target = spec.wire.radius_m;
    double poured_volume = 0.0;
    // Wire nodes within the nozzle's reach (2 r_w) along the chain behind it, + 1.
    const auto own_nodes = static_cast<std::size_t>(std::ceil(3.0 * spec.wire.radius_m / spec.wire.segment_length_m)) + 1;
    const auto expected_steps = static_cast<std::uint64_t>((pour_time + 0.1) / dt);
    std::uint64_t steps = 0;

    auto fill_now = [&] { return poured_volume / (assumed_packing_fraction * std::numbers::pi * R * R); };
    auto step_once = [&]() -> std::string {
        if (control.cancel && control.cancel->load()) return "cancelled";
        if (sim.step().blew_up) return "the simulation blew up during preparation (time step too large?)";
        ++steps;
        if (control.progress && control.progress_every && steps % control.progress_every == 0)
            control.progress(steps, std::max(expected_steps, steps));
        return {};
    };

    // Pouring and laying.
    while (w.of(BodyKind::grain).size() < spec.grain_count) {
        if (w.time_s > spec.max_time_s) return Err(std::string("preparation exceeded max_preparation_time_s while pouring"));
        if (w.time_s >= next_batch) {
            owed += grains_per_s * batch_interval;
            const double zone_low = fill_now() + 3.0 * r_max + std::max(0.0, nozzle.z_m() - fill_now());
            const int attempts = static_cast<int>(std::ceil(owed)) * 20;
            for (int a = 0; a < attempts && owed >= 1.0 && w.of(BodyKind::grain).size() < spec.grain_count; ++a) {
                const double radius = spec.grain_radius_m * (1.0 + spec.grain_radius_spread * (2.0 * rng.uniform() - 1.0));
                const double rho = pour_radius * std::sqrt(rng.uniform()), phi = 2.0 * std::numbers::pi * rng.uniform();
                const Vec3 x(rho * std::cos(phi), rho * std::sin(phi), zone_low + zone_height * rng.uniform());
                bool free = true;
                for (int k = 0; k < 2 && free; ++k) {
                    const TranslationalState& b = w.bodies[k];
                    for (std::size_t i = b.size(); i-- > 0 && free;) // the newest bodies are the likeliest neighbours
                        free = (b.x[0][i] - x).norm() >= radius + b.radius_m[i] + 0.1 * r_max;
                }
                if (!free) continue;
                add_grain(w, x, radius, grain_mat, Vec3(0, 0, -spec.pour_speed_m_per_s));
                poured_volume += 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
                owed -= 1.0;
            }
            next_batch += batch_interval;
        }
        if (with_wire) {
            // The pile under the nozzle, refreshed every 100 steps. The nozzle
            // climbs over earlier wire, but stays within 2 r_max of the fill
            // height: a wire laid faster than the grains bury it would
            // otherwise lift the nozzle out of the pile, loop after loop.
            if (steps % 100 == 0)
                nozzle_target = std::min(std::max(fill_now(), local_top_m(w, nozzle.position(), 2.0 * spec.wire.radius_m, own_nodes)),
                                    fill_now() + 2.0 * r_max)
                              + 1.1 * spec.wire.radius_m;
            nozzle.advance(w, dt, nozzle_target);
            if (w.point_loads.size() != w.of(BodyKind::wire).size())
                set_weights(w, spec.density_scale, spec.node_mass_scale, spec.density_scale);
        }
        if (std::string e = step_once(); !e.empty()) return Err(e);
    }

    Nozzle::release_end(w); // the laying is over: the wire's ends are free (the model spec §3)

    // Settling: the kinetic energy per grain, with the masses scaled by s only
    // (the nodes' extra inertia M does not count), below the threshold × s.
    PreparationReport report;
    const auto check_every = static_cast<std::uint64_t>(std::max(1.0, 1e-3 / dt));
    for (;;) {
        if (std::string e = step_once(); !e.empty()) return Err(e);
        if (steps % check_every == 0) {
            const double ke = settling_energy_j(w, spec.node_mass_scale);
            if (ke / static_cast<double>(w.of(BodyKind::grain).size())
                < spec.settle_kinetic_energy_per_grain_j * spec.density_scale) {
                report.settled = true;
                break;
            }
            if (w.time_s > spec.max_time_s) break;
        }
    }
    w.walls.erase(w.walls.begin() + static_cast<std::ptrdiff_t>(mould_wall)); // the mould goes before the lid
    w.kinds_interact[1][2] = w.kinds_interact[2][1] = wire_touches_membrane;
    w.neighbours_dirty = true;

    // Lower the top plate until it touches the pile.
    double top = 0.0;
    for (int k = 0; k < 2; ++k)
        for (std::size_t i = 0; i < w.bodies[k].size(); ++i)
            top = std::max(top, w.bodies[k].x[0][i].z() + w.bodies[k].radius_m[i]);
    Wall lid = make_plate(top + 0.5 * r_max, -1.0, plate_mat);
    lid.velocity_m_per_s = Vec3(0, 0, -spec.plate_speed_m_per_s);
    report.top_plate_wall = add_wall(w, lid);
    while (w.walls[report.top_plate_wall].contacts == 0) {
        if (std::string e = step_once(); !e.empty()) return Err(e);
        if (w.walls[report.top_plate_wall].point_m.z() < 0.5 * top)
            return Err(std::string("the top plate went through the pile without touching it"));
    }
    w.walls[report.top_plate_wall].velocity_m_per_s.setZero();

    const TranslationalState& g = w.of(BodyKind::grain);
    double grain_volume = 0.0;
    for (double r : g.radius_m) grain_volume += 4.0 / 3.0 * std::numbers::pi * r * r * r;
    report.grains = g.size();
    report.wire_nodes = w.of(BodyKind::wire).size();
    report.wire_length_m = wire_length_m(w);
    report.pile_height_m = w.walls[report.top_plate_wall].point_m.z();
    report.sample_volume_m3 = std::numbers::pi * R * R * report.pile_height_m;
    report.grain_volume_fraction = grain_volume / report.sample_volume_m3;
    report.wire_volume_fraction = std::numbers::pi * spec.wire.radius_m * spec.wire.radius_m
                                * report.wire_length_m / report.sample_volume_m3;
    report.simulated_time_s = w.time_s;
    report.steps = steps;
    report.time_step_s = dt;
    report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return report;
}

} // namespace wiredem::engine
