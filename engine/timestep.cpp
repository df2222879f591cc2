#include "timestep.hpp"

#include "core/format.hpp"
#include "forces/wire_forces.hpp"
#include "laws/hertz.hpp"

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

bool StableStep::overdamped() const { return critical_s < min_damped_step_fraction * undamped_critical_s; }

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
    present = true;
    max_plane_modulus_pa = std::max(max_plane_modulus_pa, plane_modulus_pa);
    min_radius_m = std::min(min_radius_m, radius_m);
    if (!held) {
        min_mass_kg = std::min(min_mass_kg, mass_kg);
        moving = true;
    }
}

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
                in.kinds[k].include(clump_sphere_effective_mass_kg(w, i), false, b.radius_m[i], modulus);
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
    if (!w.membrane.node_mass_kg.empty() && deformable) { // a rigid membrane does not oscillate
        in.membrane_edge_stiffness_n_per_m = w.membrane.edge_stiffness_n_per_m;
        in.membrane_node_mass_kg = *std::min_element(w.membrane.node_mass_kg.begin(), w.membrane.node_mass_kg.end());
    }
    return in;
}

StableStep stable_time_step(const StabilityInputs& in, double impact_speed_m_per_s)
{
    StableStep c;
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
            fold_contact_limit(c, in, k, m, std::string(kind_name(a)) + "–" + kind_name(b) + " contacts");
        }
    // Body–wall contacts.
    for (const double wall_modulus : in.wall_plane_moduli_pa)
        for (int k = 0; k < body_kind_count; ++k) {
            if (!kinds[k].moving) continue;
            const double e_star = 1.0 / (1.0 / kinds[k].max_plane_modulus_pa + 1.0 / wall_modulus);
            const double r = kinds[k].min_radius_m;
            const double overlap = std::max(reference_overlap_fraction * r,
                impact_speed_m_per_s > 0.0 ? hertz_max_overlap_m(kinds[k].min_mass_kg, impact_speed_m_per_s, e_star, r) : 0.0);
            const double kk = hertz_stiffness_n_per_m(overlap, e_star, r);
            fold_contact_limit(c, in, kk, kinds[k].min_mass_kg, std::string(kind_name(k)) + "–wall contacts");
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
    // the stiffest oscillation); damping lowers only the ceiling.
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

LiveContactLimit live_contact_limit(const World& w, ThreadPool& pool)
{
    // Both bounds fall as ω rises (the damped one through ζ = ω γ_n / 3), so
    // the contact of the largest ω² = k/m sets the limit: one pass for it,
    // then its step. The pass runs every live_check_steps on the caller
    // between two steps; alone it was 1.7 % of a 1-thread test of the study
    // column and 1.3 % of a 2-thread one's samples (perf), all on one thread.
    const ContactList& c = w.contacts;
    struct Stiffest {
        double omega2 = 0.0;
        std::size_t contact = 0;
        bool found = false;
    };
    const Stiffest stiffest_of_all = reduce_blocks(pool, c.size(), Stiffest{},
        [&](std::size_t begin, std::size_t end) {
            Stiffest s;
            for (std::size_t p = begin; p < end; ++p) {
                if (!c.touching[p] || !(c.output[p].overlap_m > 0.0)) continue;
                const double m = std::min(contact_mass_kg(w, c.first[p]), contact_mass_kg(w, c.second[p]));
                // dF/dξ of (4/3) E* √R* ξ^{3/2}: (3/2) prefactor √ξ = 2 E* √(R* ξ).
                const double omega2 = 1.5 * c.hertz_coefficient[p] * std::sqrt(c.output[p].overlap_m) / m; // 0 when held
                if (omega2 > s.omega2) s = {omega2, p, true};
            }
            return s;
        },
        // In block order, a later block only when strictly stiffer: the first
        // of equals, as the serial pass.
        [](const Stiffest& a, const Stiffest& b) { return b.found && b.omega2 > a.omega2 ? b : a; });
    const std::size_t stiffest = stiffest_of_all.found ? stiffest_of_all.contact : c.size();
    LiveContactLimit out;
    if (stiffest == c.size()) return out;
    const std::size_t p = stiffest;
    out.overlap_m = c.output[p].overlap_m;
    out.stiffness_n_per_m = 1.5 * c.hertz_coefficient[p] * std::sqrt(out.overlap_m);
    out.mass_kg = std::min(contact_mass_kg(w, c.first[p]), contact_mass_kg(w, c.second[p]));
    const double omega = std::sqrt(out.stiffness_n_per_m / out.mass_kg);
    out.critical_s = damped_stability_limit(w.integrator, omega * w.contact.normal_damping_s / 3.0) / omega;
    out.reference_overlap_m
        = reference_overlap_fraction * effective_radius_m(radius_m(w, c.first[p]), radius_m(w, c.second[p]));
    out.kinds = side_name(c.first[p]) + "–" + side_name(c.second[p]);
    return out;
}

LiveContactLimit live_contact_limit(const World& w)
{
    ThreadPool caller_alone(1);
    return live_contact_limit(w, caller_alone);
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

} // namespace wiredem::engine
