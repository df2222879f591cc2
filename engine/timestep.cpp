#include "timestep.hpp"

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

/// Folds in a spring-type limit: ω² = k/m for a stiffness k [N/m] on a mass m [kg].
void fold_spring_limit(StableStep& c, double omega2_per_s2, const std::string& what)
{
    if (!(omega2_per_s2 > 0.0)) return;
    const double dt = gear5_stability_limit / std::sqrt(omega2_per_s2);
    if (c.critical_s == 0.0 || dt < c.critical_s) {
        c.critical_s = dt;
        c.limited_by = what;
    }
}

} // namespace

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
            fold_spring_limit(c, k / m, std::string(kind_name(a)) + "–" + kind_name(b) + " contacts");
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
            fold_spring_limit(c, kk / kinds[k].min_mass_kg, std::string(kind_name(k)) + "–wall contacts");
        }
    // Springs: the highest chain mode of the wire has ω² = 4 k_elo/m; a node of
    // the membrane mesh has six edges, bounded (Gershgorin) by ω² ≤ 12 k_m/m.
    if (in.wire_node_mass_kg > 0.0)
        fold_spring_limit(c, 4.0 * in.wire_segment_stiffness_n_per_m / in.wire_node_mass_kg, "wire segments");
    if (in.membrane_node_mass_kg > 0.0)
        fold_spring_limit(c, 12.0 * in.membrane_edge_stiffness_n_per_m / in.membrane_node_mass_kg, "membrane edges");
    c.auto_s = auto_time_step_fraction * c.critical_s;
    return c;
}

StableStep stable_time_step(const World& w, double impact_speed_m_per_s)
{
    return stable_time_step(stability_inputs(w), impact_speed_m_per_s);
}

} // namespace wiredem::engine
