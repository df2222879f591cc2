#include "timestep.hpp"

#include "core/format.hpp"
#include "forces/wire_forces.hpp"
#include "laws/hertz.hpp"
#include "laws/tangential_mode.hpp"

#include <algorithm>
#include <cmath>

namespace wiredem::engine {

namespace {

const char* kind_name(int k)
{
    static const char* names[] = {"grain", "wire node", "membrane node"};
    return names[k];
}

/// Folds in one oscillation of angular frequency ω with damping ratio ζ:
/// the undamped bound gear5_stability_limit / ω, and the damped one.
void fold_limit(StableStep& c, Integrator integrator, double omega, double damping_ratio, const std::string& what)
{
    if (!(omega > 0.0)) return;
    const double undamped = gear5_stability_limit / omega;
    if (c.undamped_critical_s == 0.0 || undamped < c.undamped_critical_s) c.undamped_critical_s = undamped;
    const double dt = std::min(undamped, damped_stability_limit(integrator, damping_ratio) / omega);
    if (c.critical_s == 0.0 || dt < c.critical_s) {
        c.critical_s = dt;
        c.limited_by = what;
    }
}

/// Folds in a spring of ω² = k/m [N/m over kg] with damping ratio ζ.
void fold_spring_limit(StableStep& c, Integrator integrator, double omega2_per_s2, double damping_ratio,
    const std::string& what)
{
    if (!(omega2_per_s2 > 0.0)) return;
    fold_limit(c, integrator, std::sqrt(omega2_per_s2), damping_ratio, what);
}

/// Folds in a Hertz contact on a mass m of tangent stiffness k at the
/// deepest overlap it is expected to reach (its fastest impact's, or the
/// reference). Both bounds take that stiffness: the damping ratio
/// ζ = ω γ_n / 3 grows with the overlap (c/m = k γ_n √ξ / m, as √ξ), and
/// taken at the reference overlap instead, runs whose impacts press deeper
/// blew up (docs/model.md, "Damping at impact overlaps").
void fold_contact_limit(StableStep& c, const StabilityInputs& in, double k_n_per_m, double m_kg, const std::string& what)
{
    const double omega = std::sqrt(k_n_per_m / m_kg);
    fold_limit(c, in.integrator, omega, omega * in.normal_damping_s / 3.0, what);
}

/// Folds in the tangential and rolling springs of a contact, ω² [1/s²]:
/// undamped, as a packing's (springs_critical_step_s), into the critical
/// step (not into the undamped step `auto` takes its fraction of: the
/// springs are bounded, not resolved; docs/model.md, "The tangential and
/// rolling springs in the step").
void fold_springs_limit(StableStep& c, double omega2_per_s2, const std::string& what)
{
    if (!(omega2_per_s2 > 0.0)) return;
    const double dt = springs_critical_step_s(omega2_per_s2);
    c.springs_critical_s = std::min(c.springs_critical_s, dt);
    if (c.critical_s == 0.0 || dt < c.critical_s) {
        c.critical_s = dt;
        c.limited_by = what;
    }
}

/// The normal force at the reference overlap, where the step takes the
/// tangential and rolling springs: the load a packing holds, not a pour's
/// impact, which lasts about one normal period, too short for a sticking
/// mode to grow (taken at the impact's overlap, they cut tiny.json's pour
/// step from 16.39 to 5.13 µs) [N].
double reference_force_n(double eff_modulus_pa, double eff_radius_m)
{
    const double overlap = reference_overlap_fraction * eff_radius_m;
    return hertz_prefactor(eff_modulus_pa, eff_radius_m) * overlap * std::sqrt(overlap);
}

/// ω² of the springs of a contact of effective radius R* whose normal force
/// is `normal_force_n`, on a side of the mobility and 1/I given, μ its
/// friction coefficient (0: no tangential spring).
double springs_omega2(const StabilityInputs& in, double normal_force_n, double eff_radius_m, double friction_coeff,
    double tangential_mobility_per_kg, double inverse_inertia_per_kg_m2)
{
    const double k = in.tangential_stiffness_per_m * normal_force_n;
    const double k_r = in.rolling_stiffness_factor * k * eff_radius_m * eff_radius_m;
    return tangential_omega2(friction_coeff > 0.0 ? k : 0.0, tangential_mobility_per_kg, k_r, inverse_inertia_per_kg_m2);
}

} // namespace

double damped_stability_limit(Integrator integrator, double damping_ratio)
{
    const double zeta = std::max(damping_ratio, 0.0);
    if (integrator == Integrator::verlet)
        return std::min(gear5_stability_limit, 2.0 * (std::sqrt(1.0 + zeta * zeta) - zeta));
    // ω δt ζ ≤ gear5_damping_limit / 2, written so that ζ = 0 divides nothing.
    return zeta * gear5_stability_limit <= 0.5 * gear5_damping_limit ? gear5_stability_limit
                                                                      : 0.5 * gear5_damping_limit / zeta;
}

bool StableStep::overdamped() const
{
    return critical_s < min_damped_step_fraction * std::min(undamped_critical_s, springs_critical_s);
}

std::string overdamped_error(const StableStep& s, double normal_damping_s)
{
    const auto text = [](double x) { return format_number(x); }; // what std::setprecision(3) wrote
    return "the contacts' normal damping γ_n = " + text(normal_damping_s) + " s leaves a stable time step of "
           + text(s.critical_s) + " s (set by the " + s.limited_by + "), under " + text(min_damped_step_fraction)
           + " of the undamped " + text(s.undamped_critical_s)
           + " s: lower the normal damping (a larger restitution), or take the verlet integrator, whose bound damping lowers far less";
}

void StabilityInputs::Kind::include(double mass_kg, bool held, double radius_m, double plane_modulus_pa)
{
    include(mass_kg, held, radius_m, plane_modulus_pa, 1.0 / mass_kg, 0.0);
}

void StabilityInputs::Kind::include(double mass_kg, bool held, double radius_m, double plane_modulus_pa,
    double tangential_mobility_per_kg, double inverse_inertia_per_kg_m2)
{
    present = true;
    max_plane_modulus_pa = std::max(max_plane_modulus_pa, plane_modulus_pa);
    min_radius_m = std::min(min_radius_m, radius_m);
    if (!held) {
        min_mass_kg = std::min(min_mass_kg, mass_kg);
        max_tangential_mobility_per_kg = std::max(max_tangential_mobility_per_kg, tangential_mobility_per_kg);
        max_inverse_inertia_per_kg_m2 = std::max(max_inverse_inertia_per_kg_m2, inverse_inertia_per_kg_m2);
        moving = true;
    }
}

namespace {

/// The sideways mobility of a contact point at lever arm `arm_m` from the
/// centre of clumped sphere `grain`, bounded over directions: the clump's
/// 1/M, and its rotation about its centre through the arm |b| + a, with
/// its smallest principal inertia [1/kg].
double clump_sphere_tangential_mobility_per_kg(const World& w, std::size_t grain, double arm_m)
{
    const ClumpState& c = w.clumps;
    const std::uint32_t clump = c.member_clump[grain];
    const double lever = c.member_offset_m[grain].norm() + arm_m;
    return 1.0 / c.mass_kg[clump] + lever * lever / c.principal_inertia_kg_m2[clump].minCoeff();
}

/// 1/I_min of the clump of clumped sphere `grain`: the most it turns under a torque [1/(kg·m²)].
double clump_inverse_inertia_per_kg_m2(const World& w, std::size_t grain)
{
    return 1.0 / w.clumps.principal_inertia_kg_m2[w.clumps.member_clump[grain]].minCoeff();
}

/// μ of a wall's contacts: its own, or the contact law's.
double wall_friction_coeff(const World& w, const Wall& wall)
{
    return wall.friction_coeff.value_or(w.contact.tangential.friction_coeff);
}

/// The contact law's tangential and rolling springs: k_t, μ (every wall's
/// own), f_r while rolling is on.
void include_spring_laws(StabilityInputs& in, const World& w)
{
    in.tangential_stiffness_per_m = w.contact.tangential.stiffness_per_m;
    in.friction_coeff = w.contact.tangential.friction_coeff;
    for (const Wall& wall : w.walls) in.wall_friction_coeffs.push_back(wall_friction_coeff(w, wall));
    in.rolling_stiffness_factor = w.contact.rolling.on() ? w.contact.rolling.stiffness_factor : 0.0;
}

} // namespace

StabilityInputs stability_inputs(const World& w, MembraneAs membrane)
{
    StabilityInputs in;
    const bool deformable = membrane == MembraneAs::deformable || !w.membrane.rigid;
    for (int k = 0; k < body_kind_count; ++k) {
        const TranslationalState& b = w.bodies[k];
        // A membrane made deformable gets its node masses, and only its rim
        // rows stay held (set_membrane_rigid); nodes added by hand, without
        // build_membrane, have no such masses and count as they are.
        const bool as_deformable_membrane = k == static_cast<int>(BodyKind::membrane) && membrane == MembraneAs::deformable
                                         && w.membrane.node_mass_kg.size() == b.size();
        for (std::size_t i = 0; i < b.size(); ++i) {
            const double modulus = plane_modulus_pa(w.materials[b.material[i]]);
            if (as_deformable_membrane)
                in.kinds[k].include(w.membrane.node_mass_kg[i], w.membrane.node_fixed[i] != 0, b.radius_m[i], modulus);
            else if (b.motion[i] == Motion::clumped) // its clump's mass as its contacts feel it
                in.kinds[k].include(clump_sphere_effective_mass_kg(w, i), false, b.radius_m[i], modulus,
                    clump_sphere_tangential_mobility_per_kg(w, i, b.radius_m[i]), clump_inverse_inertia_per_kg_m2(w, i));
            else if (k == static_cast<int>(BodyKind::grain)) { // a grain turns: 1/m + r²/I (lever arm a ≤ r)
                const double inv_inertia = w.grain_rotation.inv_inertia_per_kg_m2[i];
                in.kinds[k].include(b.mass_kg[i], !is_dynamic(b, i), b.radius_m[i], modulus,
                    1.0 / b.mass_kg[i] + b.radius_m[i] * b.radius_m[i] * inv_inertia, inv_inertia);
            }
            else
                in.kinds[k].include(b.mass_kg[i], !is_dynamic(b, i), b.radius_m[i], modulus);
        }
    }
    in.kinds_interact = w.kinds_interact;
    for (const Wall& wall : w.walls) in.wall_plane_moduli_pa.push_back(plane_modulus_pa(w.materials[wall.material]));
    if (w.of(BodyKind::wire).size() >= 2) {
        in.wire_segment_stiffness_n_per_m = w.wire.axial_stiffness_n_per_m;
        in.wire_node_mass_kg = w.wire.node_mass_kg;
    }
    in.normal_damping_s = w.contact.normal_damping_s;
    in.integrator = w.integrator;
    include_spring_laws(in, w);
    if (!w.membrane.node_mass_kg.empty() && deformable) { // a rigid membrane does not oscillate
        in.membrane_edge_stiffness_n_per_m = w.membrane.edge_stiffness_n_per_m;
        in.membrane_node_mass_kg = *std::min_element(w.membrane.node_mass_kg.begin(), w.membrane.node_mass_kg.end());
    }
    return in;
}

StableStep stable_time_step(const StabilityInputs& in, double impact_speed_m_per_s)
{
    StableStep c;
    constexpr int grain_kind = static_cast<int>(BodyKind::grain); // the kind that turns and rolls
    const auto& kinds = in.kinds;
    // Body–body contacts: k at the reference overlap with the stiffest pair of moduli
    // and the smallest radii; ω² = k/m* with the lighter body's reduced mass.
    for (int a = 0; a < body_kind_count; ++a)
        for (int b = a; b < body_kind_count; ++b) {
            if (!in.kinds_interact[a][b] || !kinds[a].present || !kinds[b].present) continue;
            if (!kinds[a].moving && !kinds[b].moving) continue;
            const double e_star = 1.0 / (1.0 / kinds[a].max_plane_modulus_pa + 1.0 / kinds[b].max_plane_modulus_pa);
            const double r_star = effective_radius_m(kinds[a].min_radius_m, kinds[b].min_radius_m);
            // The lighter moving body bounds the reduced mass from above: m* ≤ m_min.
            const double m = std::min(kinds[a].min_mass_kg, kinds[b].min_mass_kg);
            const double overlap = std::max(reference_overlap_fraction * r_star,
                impact_speed_m_per_s > 0.0 ? hertz_max_overlap_m(m, impact_speed_m_per_s, e_star, r_star) : 0.0);
            const double k = hertz_stiffness_n_per_m(overlap, e_star, r_star);
            const std::string pair = std::string(kind_name(a)) + "–" + kind_name(b);
            fold_contact_limit(c, in, k, m, pair + " contacts");
            // Its springs at the reference overlap's force, on the more mobile
            // moving side alone, as the normal contact takes the lighter body
            // alone (m* ≤ m_min), and as a packing's: springs_coordination
            // such contacts on one body (springs_critical_step_s; docs/
            // model.md, "The tangential and rolling springs in the step").
            // Only grain–grain contacts roll.
            const bool rolls = a == grain_kind && b == grain_kind;
            const double force_n = reference_force_n(e_star, r_star);
            const auto side_omega2 = [&](int kind) {
                if (!kinds[kind].moving) return 0.0;
                return springs_omega2(in, force_n, r_star, in.friction_coeff, kinds[kind].max_tangential_mobility_per_kg,
                    rolls ? kinds[kind].max_inverse_inertia_per_kg_m2 : 0.0);
            };
            fold_springs_limit(c, std::max(side_omega2(a), side_omega2(b)),
                pair + " tangential and rolling springs");
        }
    // Body–wall contacts.
    for (std::size_t wall = 0; wall < in.wall_plane_moduli_pa.size(); ++wall)
        for (int k = 0; k < body_kind_count; ++k) {
            if (!kinds[k].moving) continue;
            const double e_star = 1.0 / (1.0 / kinds[k].max_plane_modulus_pa + 1.0 / in.wall_plane_moduli_pa[wall]);
            const double r = kinds[k].min_radius_m;
            const double overlap = std::max(reference_overlap_fraction * r,
                impact_speed_m_per_s > 0.0 ? hertz_max_overlap_m(kinds[k].min_mass_kg, impact_speed_m_per_s, e_star, r) : 0.0);
            const double kk = hertz_stiffness_n_per_m(overlap, e_star, r);
            fold_contact_limit(c, in, kk, kinds[k].min_mass_kg, std::string(kind_name(k)) + "–wall contacts");
            const double friction = wall < in.wall_friction_coeffs.size() ? in.wall_friction_coeffs[wall] : in.friction_coeff;
            fold_springs_limit(c,
                springs_omega2(in, reference_force_n(e_star, r), r, friction,
                    kinds[k].max_tangential_mobility_per_kg, k == grain_kind ? kinds[k].max_inverse_inertia_per_kg_m2 : 0.0),
                std::string(kind_name(k)) + "–wall tangential and rolling springs");
        }
    // Springs: the highest chain mode of the wire has ω² = 4 k_elo/m; a node of
    // the membrane mesh has six edges, bounded (Gershgorin) by ω² ≤ 12 k_m/m.
    if (in.wire_node_mass_kg > 0.0)
        fold_spring_limit(c, in.integrator, 4.0 * in.wire_segment_stiffness_n_per_m / in.wire_node_mass_kg,
            wire_damping_ratio, "wire segments"); // its highest mode's Kelvin–Voigt damping
    if (in.membrane_node_mass_kg > 0.0)
        fold_spring_limit(c, in.integrator, 12.0 * in.membrane_edge_stiffness_n_per_m / in.membrane_node_mass_kg, 0.0,
            "membrane edges");
    // Accuracy asks for a fraction of the undamped step (steps per period of
    // the stiffest oscillation); damping and the tangential and rolling
    // springs lower only the ceiling (the springs are kept inside Gear-5's
    // bound, not resolved: docs/model.md, "The tangential and rolling
    // springs in the step").
    c.auto_s = std::min(auto_time_step_fraction * c.undamped_critical_s, c.critical_s);
    return c;
}

StableStep stable_time_step(const World& w, double impact_speed_m_per_s)
{
    return stable_time_step(stability_inputs(w), impact_speed_m_per_s);
}

namespace {

/// The mass a contact on body `r` feels, or infinity for a body that does
/// not move by forces (held, kinematic, or a wall): as stability_inputs
/// takes it (a clump's sphere: clump_sphere_effective_mass_kg).
double contact_mass_kg(const World& w, BodyRef r)
{
    if (is_wall(r)) return std::numeric_limits<double>::infinity();
    const TranslationalState& b = w.of(r.kind());
    const std::size_t i = r.index();
    if (b.motion[i] == Motion::clumped) return clump_sphere_effective_mass_kg(w, i);
    return is_dynamic(b, i) ? b.mass_kg[i] : std::numeric_limits<double>::infinity();
}

/// A contact side's radius; infinity for a wall.
double radius_m(const World& w, BodyRef r)
{
    return is_wall(r) ? std::numeric_limits<double>::infinity() : w.of(r.kind()).radius_m[r.index()];
}

std::string side_name(BodyRef r) { return is_wall(r) ? "wall" : kind_name(static_cast<int>(r.kind())); }

} // namespace

namespace {

/// The sideways mobility of body `r`'s contact point at lever arm `arm_m`
/// (tangential) and its 1/I for the rolling spring, or zeros for a body
/// that does not move by forces: as stability_inputs takes them.
struct SideMobility {
    double tangential_per_kg = 0.0;
    double inverse_inertia_per_kg_m2 = 0.0;
};

SideMobility side_mobility(const World& w, BodyRef r, double arm_m)
{
    if (is_wall(r)) return {};
    const TranslationalState& b = w.of(r.kind());
    const std::size_t i = r.index();
    if (b.motion[i] == Motion::clumped) {
        return {clump_sphere_tangential_mobility_per_kg(w, i, arm_m), clump_inverse_inertia_per_kg_m2(w, i)};
    }
    if (!is_dynamic(b, i)) return {};
    if (r.kind() != BodyKind::grain) return {1.0 / b.mass_kg[i], 0.0}; // a node does not turn
    const double inv_inertia = w.grain_rotation.inv_inertia_per_kg_m2[i];
    return {1.0 / b.mass_kg[i] + arm_m * arm_m * inv_inertia, inv_inertia};
}

/// ω² of contact p's sticking springs at this step's F_n, on its more
/// mobile moving side (0 when its tangential spring slides or it has none
/// and does not roll).
double live_springs_omega2(const World& w, std::size_t p, double& stiffness_n_per_m)
{
    const ContactList& c = w.contacts;
    const bool wall = is_wall(c.second[p]);
    const double friction = wall ? wall_friction_coeff(w, w.walls[c.second[p].index()]) : w.contact.tangential.friction_coeff;
    const bool sticks = c.tangential[p].sticking && friction > 0.0;
    const bool rolls = w.contact.rolling.on() && c.first[p].kind() == BodyKind::grain
                    && (wall || c.second[p].kind() == BodyKind::grain);
    if (!sticks && !rolls) return 0.0;
    const double k = w.contact.tangential.stiffness_per_m * c.output[p].normal_force_n;
    stiffness_n_per_m = k;
    const double overlap = c.output[p].overlap_m;
    const double r_a = radius_m(w, c.first[p]), r_b = radius_m(w, c.second[p]);
    const SideMobility a = side_mobility(w, c.first[p], r_a - 0.5 * overlap);
    const SideMobility b = side_mobility(w, c.second[p], wall ? 0.0 : r_b - 0.5 * overlap);
    const double r_star = wall ? r_a : effective_radius_m(r_a, r_b);
    const double k_r = rolls ? w.contact.rolling.stiffness_factor * k * r_star * r_star : 0.0;
    // The more mobile side alone, as stable_time_step takes a contact.
    return std::max(tangential_omega2(sticks ? k : 0.0, a.tangential_per_kg, k_r, a.inverse_inertia_per_kg_m2),
        tangential_omega2(sticks ? k : 0.0, b.tangential_per_kg, k_r, b.inverse_inertia_per_kg_m2));
}

} // namespace

LiveLimits live_limits(const World& w, ThreadPool& pool, bool with_springs)
{
    // Both bounds fall as ω rises (the damped one through ζ = ω γ_n / 3), so
    // the contact of the largest ω² = k/m sets the limit: one pass for it,
    // then its step; the springs' largest ω² in the same pass. The pass runs
    // every live_check_steps on the caller between two steps; alone (the
    // normal contacts only) it was 1.7 % of a 1-thread test of the study
    // column and 1.3 % of a 2-thread one's samples (perf), all on one thread.
    const ContactList& c = w.contacts;
    struct Stiffest {
        double omega2 = 0.0;
        std::size_t contact = 0;
        bool found = false;
        double springs_omega2 = 0.0;
        std::size_t springs_contact = 0;
        bool springs_found = false;
    };
    const Stiffest stiffest_of_all = reduce_blocks(pool, c.size(), Stiffest{},
        [&](std::size_t begin, std::size_t end) {
            Stiffest s;
            for (std::size_t p = begin; p < end; ++p) {
                if (!c.touching[p] || !(c.output[p].overlap_m > 0.0)) continue;
                const double m = std::min(contact_mass_kg(w, c.first[p]), contact_mass_kg(w, c.second[p]));
                // dF/dξ of (4/3) E* √R* ξ^{3/2}: (3/2) prefactor √ξ = 2 E* √(R* ξ).
                const double omega2 = 1.5 * c.hertz_coefficient[p] * std::sqrt(c.output[p].overlap_m) / m; // 0 when held
                if (omega2 > s.omega2) {
                    s.omega2 = omega2;
                    s.contact = p;
                    s.found = true;
                }
                if (!with_springs) continue;
                double k = 0.0;
                const double springs = live_springs_omega2(w, p, k);
                if (springs > s.springs_omega2) {
                    s.springs_omega2 = springs;
                    s.springs_contact = p;
                    s.springs_found = true;
                }
            }
            return s;
        },
        // In block order, a later block only when strictly stiffer: the first
        // of equals, as the serial pass.
        [](const Stiffest& a, const Stiffest& b) {
            Stiffest s = a;
            if (b.found && b.omega2 > a.omega2) {
                s.omega2 = b.omega2;
                s.contact = b.contact;
                s.found = true;
            }
            if (b.springs_found && b.springs_omega2 > a.springs_omega2) {
                s.springs_omega2 = b.springs_omega2;
                s.springs_contact = b.springs_contact;
                s.springs_found = true;
            }
            return s;
        });
    LiveLimits out;
    if (stiffest_of_all.springs_found) {
        const std::size_t p = stiffest_of_all.springs_contact;
        LiveSpringLimit& s = out.springs;
        s.omega2_per_s2 = live_springs_omega2(w, p, s.stiffness_n_per_m);
        s.normal_force_n = c.output[p].normal_force_n;
        s.critical_s = springs_critical_step_s(s.omega2_per_s2);
        s.kinds = side_name(c.first[p]) + "–" + side_name(c.second[p]);
    }
    if (!stiffest_of_all.found) return out;
    const std::size_t p = stiffest_of_all.contact;
    LiveContactLimit& l = out.contact;
    l.overlap_m = c.output[p].overlap_m;
    l.stiffness_n_per_m = 1.5 * c.hertz_coefficient[p] * std::sqrt(l.overlap_m);
    l.mass_kg = std::min(contact_mass_kg(w, c.first[p]), contact_mass_kg(w, c.second[p]));
    const double omega = std::sqrt(l.stiffness_n_per_m / l.mass_kg);
    l.critical_s = damped_stability_limit(w.integrator, omega * w.contact.normal_damping_s / 3.0) / omega;
    l.reference_overlap_m
        = reference_overlap_fraction * effective_radius_m(radius_m(w, c.first[p]), radius_m(w, c.second[p]));
    l.kinds = side_name(c.first[p]) + "–" + side_name(c.second[p]);
    return out;
}

LiveContactLimit live_contact_limit(const World& w, ThreadPool& pool) { return live_limits(w, pool, false).contact; }

LiveContactLimit live_contact_limit(const World& w)
{
    ThreadPool caller_alone(1);
    return live_contact_limit(w, caller_alone);
}

std::string live_spring_warning(const LiveSpringLimit& springs, double dt_s, const std::string& after)
{
    return after + ": the time step " + format_number(dt_s) + " s (engine.time_step_s) was " + format_number(dt_s / springs.critical_s)
           + " times the stable limit " + format_number(springs.critical_s)
           + " s " + live_spring_warning_marker + ", a " + springs.kinds + " contact at F_n = "
           + format_number(springs.normal_force_n) + " N (spring k_t F_n = " + format_number(springs.stiffness_n_per_m)
           + " N/m); such a spring breaks at its friction limit and slides instead of diverging, so the test went on, but"
             " its contacts may chatter: take a time step below "
           + format_number(springs.critical_s) + " s (engine.time_step_s) or a softer contact.tangential_stiffness_per_m";
}

std::string live_contact_error(const LiveContactLimit& live, double dt_s, const std::string& after)
{
    return "stopped " + after + ": the time step " + format_number(dt_s) + " s is " + format_number(dt_s / live.critical_s)
           + " times the stable limit " + format_number(live.critical_s) + " s of the stiffest contact now (runs beyond "
           + format_number(live_contact_tolerance) + " times it were measured to diverge), a " + live.kinds + " contact pressed to "
           + format_number(live.overlap_m) + " m (" + format_number(live.overlap_m / live.reference_overlap_m)
           + " times the reference overlap the step was set for; its stiffness grows as the square root of the overlap)"
           + ": take a time step below " + format_number(live.critical_s)
           + " s (engine.time_step_s), stiffer grains (specimen.grain.youngs_modulus_pa) or a lower pressure or load (triaxial.confining_pressures_pa, free_standing.dead_load_n)";
}

std::string blow_up_error(double dt_s, const std::string& after)
{
    return "the simulation blew up " + after + ": a position became NaN or infinite. Its time step "
           + format_number(dt_s) + " s was too large for what the run met (the stable step is set for each contact at its "
             "reference overlap; deeper impacts, pressed contacts or a packing's springs can need less): run it again with "
             "a smaller engine.time_step_s, for example "
           + format_number(0.5 * dt_s) + " s (half of it)";
}

} // namespace wiredem::engine
