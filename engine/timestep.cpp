#include "timestep.hpp"

#include "laws/hertz.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wiredem::engine {

namespace {
const char* kind_name(int k)
{
    static const char* names[] = {"grain", "wire node", "membrane node"};
    return names[k];
}
} // namespace

void fold_spring_limit(CriticalStep& c, double omega2_per_s2, const std::string& what)
{
    if (!(omega2_per_s2 > 0.0)) return;
    const double dt = gear5_stability_limit / std::sqrt(omega2_per_s2);
    if (c.critical_s == 0.0 || dt < c.critical_s) {
        c.critical_s = dt;
        c.limited_by = what;
    }
}

CriticalStep critical_time_step(const World& w, double impact_speed_m_per_s)
{
    CriticalStep c;
    struct Extremes {
        double min_mass = std::numeric_limits<double>::infinity();
        double min_radius = std::numeric_limits<double>::infinity();
        double max_modulus = 0.0; // E/(1−ν²)
        bool any = false;
    };
    std::array<Extremes, body_kind_count> kinds{};
    for (int k = 0; k < body_kind_count; ++k) {
        const TranslationalState& b = w.bodies[k];
        for (std::size_t i = 0; i < b.size(); ++i) {
            const Material& m = w.materials[b.material[i]];
            kinds[k].max_modulus = std::max(kinds[k].max_modulus, m.youngs_modulus_pa / (1 - m.poisson_ratio * m.poisson_ratio));
            kinds[k].min_radius = std::min(kinds[k].min_radius, b.radius_m[i]);
            if (b.inv_mass_per_kg[i] != 0.0) {
                kinds[k].min_mass = std::min(kinds[k].min_mass, b.mass_kg[i]);
                kinds[k].any = true;
            }
        }
    }
    // Body–body contacts: k at the reference overlap with the stiffest pair of moduli
    // and the smallest radii; ω² = k/m* with the lighter body's reduced mass.
    for (int a = 0; a < body_kind_count; ++a)
        for (int b = a; b < body_kind_count; ++b) {
            if (!w.kinds_interact[a][b] || w.bodies[a].size() == 0 || w.bodies[b].size() == 0) continue;
            if (!kinds[a].any && !kinds[b].any) continue;
            const double e_star = 1.0 / (1.0 / kinds[a].max_modulus + 1.0 / kinds[b].max_modulus);
            const double r_star = effective_radius_m(kinds[a].min_radius, kinds[b].min_radius);
            // The lighter moving body bounds the reduced mass from above: m* ≤ m_min.
            const double m = std::min(kinds[a].min_mass, kinds[b].min_mass);
            const double overlap = std::max(reference_overlap_fraction * r_star,
                impact_speed_m_per_s > 0.0 ? hertz_max_overlap_m(m, impact_speed_m_per_s, e_star, r_star) : 0.0);
            const double k = hertz_stiffness_n_per_m(overlap, e_star, r_star);
            fold_spring_limit(c, k / m, std::string(kind_name(a)) + "–" + kind_name(b) + " contacts");
        }
    // Body–wall contacts.
    for (const Wall& wall : w.walls) {
        const Material& wm = w.materials[wall.material];
        const double wall_modulus = wm.youngs_modulus_pa / (1 - wm.poisson_ratio * wm.poisson_ratio);
        for (int k = 0; k < body_kind_count; ++k) {
            if (!kinds[k].any) continue;
            const double e_star = 1.0 / (1.0 / kinds[k].max_modulus + 1.0 / wall_modulus);
            const double r = kinds[k].min_radius;
            const double overlap = std::max(reference_overlap_fraction * r,
                impact_speed_m_per_s > 0.0 ? hertz_max_overlap_m(kinds[k].min_mass, impact_speed_m_per_s, e_star, r) : 0.0);
            const double kk = hertz_stiffness_n_per_m(overlap, e_star, r);
            fold_spring_limit(c, kk / kinds[k].min_mass, std::string(kind_name(k)) + "–wall contacts");
        }
    }
    // Springs: the highest chain mode of the wire has ω² = 4 k_elo/m; a node of
    // the membrane mesh has six edges, bounded (Gershgorin) by ω² ≤ 12 k_m/m.
    const TranslationalState& wire = w.of(BodyKind::wire);
    if (wire.size() >= 2 && w.wire.node_mass_kg > 0.0)
        fold_spring_limit(c, 4.0 * w.wire.axial_stiffness_n_per_m / w.wire.node_mass_kg, "wire segments");
    if (!w.membrane.node_mass_kg.empty() && !w.membrane.rigid) { // a rigid membrane does not oscillate
        const double m = *std::min_element(w.membrane.node_mass_kg.begin(), w.membrane.node_mass_kg.end());
        if (m > 0.0) fold_spring_limit(c, 12.0 * w.membrane.edge_stiffness_n_per_m / m, "membrane edges");
    }
    return c;
}

} // namespace wiredem::engine
