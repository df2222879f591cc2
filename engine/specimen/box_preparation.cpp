// The box preparation; see box_preparation.hpp.
#include "specimen/box_preparation.hpp"

#include "core/format.hpp"
#include "core/result.hpp"
#include "scene.hpp"
#include "specimen/packing.hpp"
#include "state/clump_shape.hpp"
#include "timestep.hpp"
#include "triaxial/sampling.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

namespace wiredem::engine {
namespace {

// Attempts to place one grain in the loose box before giving up: at a volume
// fraction of 0.25 random sequential addition places a sphere within a few
// attempts (the jamming limit is ≈ 0.38).
constexpr int placement_attempts_per_grain = 1000;
// A loose box where a grain found no place is made this much looser, down to
// the floor (at 0.05 random sequential addition places any grading: far
// below its jamming limit).
constexpr double loosening_factor = 0.8;
constexpr double min_initial_packing_fraction = 0.05;
// The servo and the criteria are looked at every step; at rest is checked
// once every this many seconds of simulated time (about a grain's contact
// period at σ_c, ~10⁻⁵ s, times 10).
constexpr double rest_check_interval_s = 1e-4;
// Of the auto step (one pair's frequency): in a dense packing each grain has
// several stiff neighbours and Gear-5 at the auto step is unstable in the
// packing's highest mode, as in the FCC array (tests/validation/fcc.hpp).
// Measured on 300 grains compacted to 20 kPa: at the auto step the walls
// stayed 2.5 % off σ_c with an unbalanced force ratio of 0.88 for 1 s of
// simulated time; at half of it, at rest (ratio 0.01, walls within 1 %)
// after 0.11–0.18 s.
constexpr double box_time_step_fraction = 0.5;

std::string out_of_range(const char* field, double value, const char* range)
{
    return std::string(field) + ": " + format_number(value) + " must lie in " + range;
}

/// A drawn radius: from the curve by number, or uniform in r (1 ± spread).
double draw_radius_m(const BoxPreparationSpec& spec, const std::optional<GrainSizeDistribution>& sizes, SplitMix64& rng)
{
    if (sizes) return 0.5 * sizes->diameter_at_number_fraction(rng.uniform());
    return spec.grain_radius_m * (1.0 + spec.grain_radius_spread * (2.0 * rng.uniform() - 1.0));
}

} // namespace

std::optional<std::string> box_preparation_error(const BoxPreparationSpec& s)
{
    if (s.grain_count == 0) return std::string("grain_count: 0 must be at least 1");
    if (!s.grain_sizes && !(s.grain_radius_m > 0.0)) return out_of_range("grain_radius_m", s.grain_radius_m, "(0, ∞)");
    if (!(s.grain_radius_spread >= 0.0 && s.grain_radius_spread < 1.0))
        return out_of_range("grain_radius_spread", s.grain_radius_spread, "[0, 1)");
    if (!(s.aspect_ratio >= 0.25 && s.aspect_ratio <= 4.0)) return out_of_range("aspect_ratio", s.aspect_ratio, "[0.25, 4]");
    if (!(s.initial_packing_fraction > 0.0 && s.initial_packing_fraction <= 0.35))
        return out_of_range("initial_packing_fraction", s.initial_packing_fraction,
            "(0, 0.35] (random sequential addition jams at about 0.38)");
    if (!(s.consolidation_pressure_pa > 0.0 && std::isfinite(s.consolidation_pressure_pa)))
        return out_of_range("consolidation_pressure_pa", s.consolidation_pressure_pa, "(0, ∞)");
    if (s.compaction_friction_coeff && !(*s.compaction_friction_coeff >= 0.0 && std::isfinite(*s.compaction_friction_coeff)))
        return out_of_range("compaction_friction_coeff", *s.compaction_friction_coeff, "[0, ∞)");
    if (s.wall_friction_coeff && !(*s.wall_friction_coeff >= 0.0 && std::isfinite(*s.wall_friction_coeff)))
        return out_of_range("wall_friction_coeff", *s.wall_friction_coeff, "[0, ∞)");
    if (!(s.servo_relaxation > 0.0 && s.servo_relaxation <= 1.0))
        return out_of_range("servo_relaxation", s.servo_relaxation, "(0, 1]");
    if (!(s.max_wall_speed_m_per_s > 0.0 && std::isfinite(s.max_wall_speed_m_per_s)))
        return out_of_range("max_wall_speed_m_per_s", s.max_wall_speed_m_per_s, "(0, ∞)");
    if (!(s.stress_tolerance > 0.0 && s.stress_tolerance < 1.0))
        return out_of_range("stress_tolerance", s.stress_tolerance, "(0, 1)");
    if (!(s.unbalanced_force_ratio > 0.0 && s.unbalanced_force_ratio < 1.0))
        return out_of_range("unbalanced_force_ratio", s.unbalanced_force_ratio, "(0, 1)");
    if (!(s.max_time_s > 0.0 && std::isfinite(s.max_time_s))) return out_of_range("max_time_s", s.max_time_s, "(0, ∞)");
    if (!(s.time_step_s >= 0.0 && std::isfinite(s.time_step_s))) return out_of_range("time_step_s", s.time_step_s, "[0, ∞)");
    return std::nullopt;
}

Result<BoxPreparationSpec, std::string> box_preparation_from(
    const PreparationSpec& poured, double consolidation_pressure_pa, std::optional<double> wall_friction_coeff)
{
    BoxPreparationSpec box;
    box.grain_count = poured.grain_count;
    box.grain_radius_m = poured.grain_radius_m;
    box.grain_radius_spread = poured.grain_radius_spread;
    box.grain_sizes = poured.grain_sizes;
    box.grain_shape = poured.grain_shape;
    box.grain = poured.grain;
    box.grain.density_kg_per_m3 *= poured.density_scale;
    box.wall = poured.plate;
    box.contact = poured.contact;
    box.integrator = poured.integrator;
    box.time_step_s = poured.time_step_s;
    box.seed = poured.seed;
    box.max_time_s = poured.max_time_s;
    box.consolidation_pressure_pa = consolidation_pressure_pa;
    box.wall_friction_coeff = wall_friction_coeff;
    return box;
}

double unbalanced_force_ratio(const World& w)
{
    const ContactList& c = w.contacts;
    double contact_sum = 0.0;
    std::size_t contacts = 0;
    for (std::size_t p = 0; p < c.size(); ++p)
        if (c.touching[p]) contact_sum += c.output[p].force_n.norm(), ++contacts;
    if (contacts == 0) return 0.0;
    const TranslationalState& g = w.of(BodyKind::grain);
    const std::vector<Vec3>& net = w.force_of(BodyKind::grain);
    // A clump's spheres carry the contacts; the body is the clump.
    double net_sum = 0.0;
    for (std::size_t i = 0; i < g.size(); ++i)
        if (!w.clumps.is_member(i)) net_sum += net[i].norm();
    for (const Vec3& f : w.clump_loads.force_n) net_sum += f.norm();
    return (net_sum / static_cast<double>(grain_body_count(w))) / (contact_sum / static_cast<double>(contacts));
}

Result<BoxPreparationReport, std::string> prepare_box_specimen(
    Simulation& sim, const BoxPreparationSpec& spec, const RunControl& control)
{
    const auto wall_start = std::chrono::steady_clock::now();
    if (auto e = box_preparation_error(spec)) return Err(*e);
    const std::optional<GrainSizeDistribution> sizes
        = spec.grain_sizes ? std::optional<GrainSizeDistribution>(std::in_place, *spec.grain_sizes) : std::nullopt;

    // The radii first (drawn in id order), then the loose box they fill at
    // the initial packing fraction, then the places.
    SplitMix64 rng(spec.seed);
    std::vector<double> radii(spec.grain_count);
    double grain_volume_m3 = 0.0;
    for (double& r : radii) {
        r = draw_radius_m(spec, sizes, rng);
        grain_volume_m3 += 4.0 / 3.0 * std::numbers::pi * r * r * r;
    }
    // A clump is placed where its bounding sphere is free, extent k r (k its
    // shape's bounding radius per volume-equivalent radius); a sphere's
    // extent is its radius. The loose box holds the extents' spheres at the
    // initial fraction (a crushed clump's are 2.9 times its volume).
    const double k = spec.grain_shape ? spec.grain_shape->bounding_radius_m() : 1.0;
    std::vector<double> extents(radii.size());
    double extent_volume_m3 = 0.0; // the grains' volume for spheres (k = 1: the same bits)
    for (std::size_t i = 0; i < radii.size(); ++i) {
        const double e = extents[i] = k * radii[i];
        extent_volume_m3 += 4.0 / 3.0 * std::numbers::pi * e * e * e;
    }
    // The fraction is over the box the centres may take, the box less the
    // largest radius at each wall: counted over the whole box, a small box's
    // centres would crowd at the fraction of a larger one (300 grains at
    // 0.25 over the whole box: 0.36 over the centres' box, and grains
    // found no place).
    const double r_max = *std::max_element(extents.begin(), extents.end());

    // Random sequential addition: each grain at a uniform point of the box
    // its centre may take, kept if it overlaps no grain placed before (a
    // clump then turned at random, as the pour turns them). Where a grain
    // finds no place (a wide grading places some of its largest grains
    // late), the box is made looser, its fraction a fifth lower, and the
    // placing starts again with the draws going on: the first box that
    // takes every grain is kept (the compaction closes it anyway).
    struct LooseBox {
        double width_m = 0.0, height_m = 0.0;
        std::vector<Vec3> x;
        std::vector<Quat> orientation;
    };
    const auto place = [&](double fraction) -> std::optional<LooseBox> {
        LooseBox box;
        const double inner_width_m = std::cbrt(extent_volume_m3 / fraction / spec.aspect_ratio); // L² · (a L) = V
        box.width_m = inner_width_m + 2.0 * r_max;
        box.height_m = spec.aspect_ratio * inner_width_m + 2.0 * r_max;
        box.x.reserve(radii.size());
        for (std::size_t n = 0; n < radii.size(); ++n) {
            const double r = extents[n];
            bool done = false;
            for (int a = 0; a < placement_attempts_per_grain && !done; ++a) {
                // Drawn z, y, x: the order GCC took for the arguments of one
                // constructor (unspecified in C++; clang goes left to right), now
                // written out so that every compiler places the same grains.
                const double uz = rng.uniform(), uy = rng.uniform(), ux = rng.uniform();
                const Vec3 x(-0.5 * box.width_m + r + (box.width_m - 2 * r) * ux,
                    -0.5 * box.width_m + r + (box.width_m - 2 * r) * uy, r + (box.height_m - 2 * r) * uz);
                done = true;
                for (std::size_t i = 0; i < box.x.size() && done; ++i)
                    done = (box.x[i] - x).squaredNorm() >= (extents[i] + r) * (extents[i] + r);
                if (done) box.x.push_back(x);
            }
            if (!done) return std::nullopt;
            if (spec.grain_shape) {
                const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
                box.orientation.push_back(uniform_orientation(u1, u2, u3));
            }
        }
        return box;
    };
    double fraction = spec.initial_packing_fraction;
    std::optional<LooseBox> loose = place(fraction);
    while (!loose) {
        if (fraction * loosening_factor < min_initial_packing_fraction)
            return Err("the grains found no free places in a loose box of fraction " + format_number(fraction)
                       + " after " + std::to_string(placement_attempts_per_grain) + " attempts each (from "
                       + format_number(spec.initial_packing_fraction) + ", lowered to "
                       + format_number(min_initial_packing_fraction) + " at most)");
        fraction *= loosening_factor;
        loose = place(fraction);
    }
    const double width_m = loose->width_m, height_m = loose->height_m;
    const double volume_m3 = width_m * width_m * height_m;

    World& w = sim.world;
    w = World{};
    w.integrator = spec.integrator;
    w.contact = spec.contact;
    w.gravity_m_per_s2 = Vec3::Zero(); // isotropic compaction (file comment)
    const std::uint8_t grain_mat = add_material(w, spec.grain);
    const std::uint8_t wall_mat = add_material(w, spec.wall);
    const Vec3 lo(-0.5 * width_m, -0.5 * width_m, 0.0), hi(0.5 * width_m, 0.5 * width_m, height_m);
    BoxPreparationReport report;
    report.walls = add_cuboid_walls(w, lo, hi, wall_mat, spec.wall_friction_coeff);
    report.initial_volume_m3 = volume_m3;
    report.initial_packing_fraction = fraction;
    for (std::size_t n = 0; n < radii.size(); ++n) {
        if (spec.grain_shape)
            add_clump(w, scaled_clump(*spec.grain_shape, radii[n]), loose->x[n], loose->orientation[n], grain_mat);
        else
            add_grain(w, loose->x[n], radii[n], grain_mat);
    }

    // δt: a fraction of the stable step with impacts at the walls' top speed.
    const StableStep step = stable_time_step(w, 2.0 * spec.max_wall_speed_m_per_s);
    if (step.overdamped()) return Err(overdamped_error(step, w.contact.normal_damping_s));
    const double dt = spec.time_step_s > 0.0 ? spec.time_step_s : box_time_step_fraction * step.auto_s;
    if (dt > step.critical_s)
        return Err("time_step_s: " + format_number(dt) + " exceeds the stable limit " + format_number(step.critical_s)
                   + " s set by the " + step.limited_by);
    set_time_step(w, dt);

    // μ_c while compacting (file comment).
    const double mu = spec.contact.tangential.friction_coeff;
    w.contact.tangential.friction_coeff = spec.compaction_friction_coeff.value_or(mu);

    const CuboidWalls& walls = report.walls;
    const std::array<std::size_t, 5> servos{walls.top, walls.lateral[0], walls.lateral[1], walls.lateral[2], walls.lateral[3]};
    const double target = spec.consolidation_pressure_pa;
    const auto check_every = static_cast<std::uint64_t>(std::max(1.0, std::round(rest_check_interval_s / dt)));
    const auto max_steps = static_cast<std::uint64_t>(std::ceil(spec.max_time_s / dt));
    // The walls close the loose box by ~(1 − (φ₀/0.6)^{1/3}) of its width at
    // the speed cap: the expected length, for progress only.
    const auto expected_steps = static_cast<std::uint64_t>(
        std::ceil(0.5 * width_m * (1.0 - std::cbrt(fraction / 0.6)) / spec.max_wall_speed_m_per_s / dt)
        + 10 * check_every);
    std::uint64_t steps = 0;
    for (; steps < max_steps; ++steps) {
        if (control.cancel && control.cancel->load()) return Err(std::string("cancelled"));
        // Each moving wall towards σ_c (the cell's servo: cuboid.hpp). The
        // first step has no contacts: every wall closes at the cap.
        const CuboidStresses box = cuboid_stresses(w, walls);
        const std::array<double, 5> measured{box.sigma_z_pa, box.lateral_pa[0], box.lateral_pa[1], box.lateral_pa[2], box.lateral_pa[3]};
        const std::array<double, 5> area{box.width_x_m * box.width_y_m, box.width_y_m * box.height_m,
            box.width_y_m * box.height_m, box.width_x_m * box.height_m, box.width_x_m * box.height_m};
        if (steps > 0 && steps % check_every == 0) {
            bool held = true;
            for (const double s : measured) held = held && std::abs(s - target) <= spec.stress_tolerance * target;
            if (held && unbalanced_force_ratio(w) <= spec.unbalanced_force_ratio) {
                report.at_rest = true;
                break;
            }
        }
        for (std::size_t i = 0; i < servos.size(); ++i) {
            // The top closes the height alone (the bottom is fixed) while two
            // walls close each width: twice the cap, so that the loose box
            // shrinks at one strain rate in every direction.
            const double cap = (i == 0 ? 2.0 : 1.0) * spec.max_wall_speed_m_per_s;
            const double v = servo_wall_speed_m_per_s(
                target, measured[i], area[i], wall_response(w, servos[i]), dt, spec.servo_relaxation, cap);
            w.walls[servos[i]].velocity_m_per_s = v * w.walls[servos[i]].normal;
        }
        if (sim.step().blew_up)
            return Err(blow_up_error(w.dt_s, "after " + std::to_string(steps + 1) + " steps of the box's compaction, at t = "
                                                 + format_number(w.time_s) + " s"));
        if (control.progress && control.progress_every && (steps + 1) % control.progress_every == 0)
            control.progress(steps + 1, std::max(expected_steps, steps + 1));
    }
    for (const std::size_t i : servos) w.walls[i].velocity_m_per_s.setZero();
    w.contact.tangential.friction_coeff = mu;

    report.grains = radii.size();
    report.box = cuboid_stresses(w, walls);
    report.sample_volume_m3 = report.box.width_x_m * report.box.width_y_m * report.box.height_m;
    report.grain_volume_fraction = grain_volume_m3 / report.sample_volume_m3;
    // The box now (the walls have moved in from the loose box's lo, hi).
    const Vec3 now_lo(w.walls[walls.lateral[0]].point_m.x(), w.walls[walls.lateral[2]].point_m.y(), w.walls[walls.bottom].point_m.z());
    const Vec3 now_hi(w.walls[walls.lateral[1]].point_m.x(), w.walls[walls.lateral[3]].point_m.y(), w.walls[walls.top].point_m.z());
    const CoreSampling sampling = core_sampling(
        largest_grain_radius_m(spec.grain_radius_m, spec.grain_radius_spread, spec.grain_sizes, spec.grain_shape),
        spec.grain_radius_m, spec.grain_sizes);
    report.core_grain_volume_fraction = box_core_volume_fractions(w, now_lo, now_hi, sampling.margin_m, sampling.grid_m).grain;
    report.unbalanced_force_ratio = unbalanced_force_ratio(w);
    const ContactList& c = w.contacts;
    for (std::size_t p = 0; p < c.size(); ++p)
        if (c.touching[p]) report.max_overlap_m = std::max(report.max_overlap_m, c.output[p].overlap_m);
    report.steps = steps;
    report.simulated_time_s = static_cast<double>(steps) * dt;
    report.time_step_s = dt;
    if (spec.grain_sizes) report.grain_sizes = grain_size_report(radii, *spec.grain_sizes);
    report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return report;
}

} // namespace wiredem::engine
