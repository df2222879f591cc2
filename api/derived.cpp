// Derived quantities of a job: the probe world for the stable step, the
// body estimate and the damping time (see api/derived.hpp).
#include "api/derived.hpp"

#include "api/engine_settings.hpp"

#include "laws/hertz.hpp"
#include "state/world.hpp"
#include "timestep.hpp"

#include <cmath>
#include <numbers>

namespace wiredem::api {

namespace {

/// Mass of a wire node: ρ_w π r_w² l_w (the model spec §2), unscaled [kg].
double wire_node_mass_kg(const WireSpec& w)
{
    return w.density_kg_per_m3 * std::numbers::pi * w.radius_m * w.radius_m * w.segment_length_m;
}

/// Mass of a membrane node: (√3/2) l_m² ρ_m d (the model spec §2), unscaled [kg].
double membrane_node_mass_kg(const MembraneSpec& m)
{
    return 0.5 * std::numbers::sqrt3 * m.mesh_size_m * m.mesh_size_m * m.density_kg_per_m3 * m.thickness_m;
}

} // namespace

StableStep stable_time_step(const JobSpec& spec)
{
    const SpecimenSpec& s = spec.specimen;
    const double scale = spec.engine.density_scale;
    const double wire_scale = scale * spec.engine.wire_mass_scale;
    engine::World w;
    // Density scaling multiplies every mass: scale the grain density (add_grain
    // derives the mass from it) and the node masses alike; the wire's once more.
    const std::uint8_t grain = engine::add_material(w,
        {s.grain.youngs_modulus_pa, s.grain.poisson_ratio, s.grain.density_kg_per_m3 * scale});
    const std::uint8_t wire = engine::add_material(w,
        {s.wire.youngs_modulus_pa, s.wire.poisson_ratio, s.wire.density_kg_per_m3 * wire_scale});
    const std::uint8_t membrane = engine::add_material(w,
        {s.membrane.youngs_modulus_pa, s.membrane.poisson_ratio, s.membrane.density_kg_per_m3 * scale});
    const std::uint8_t plate = engine::add_material(w, {s.plate.youngs_modulus_pa, s.plate.poisson_ratio, 1.0});

    // One body of each kind, far apart: critical_time_step looks at the
    // lightest body, the smallest radius and the stiffest material per kind.
    const double smallest_grain_m = s.grain_radius_m * (1.0 - s.grain_radius_spread);
    engine::add_grain(w, engine::Vec3(0.0, 0.0, 1.0), smallest_grain_m, grain);
    const bool has_wire = s.wire.pattern != WirePattern::none;
    if (has_wire)
        engine::add_node(w, engine::BodyKind::wire, engine::Vec3(0.0, 0.0, 2.0), s.wire.radius_m,
            wire_node_mass_kg(s.wire) * wire_scale, wire);
    engine::add_node(w, engine::BodyKind::membrane, engine::Vec3(0.0, 0.0, 3.0),
        membrane_contact_radius_m(s.membrane), membrane_node_mass_kg(s.membrane) * scale, membrane);
    engine::add_wall(w, engine::make_plate(0.0, 1.0, plate));

    engine::CriticalStep c = engine::critical_time_step(w);
    if (has_wire) {
        // Highest mode of a free chain: ω² = 4 k_elo / m_w, k_elo = E_w π r_w² / l_w.
        const double k_elo = s.wire.youngs_modulus_pa * std::numbers::pi * s.wire.radius_m * s.wire.radius_m
                           / s.wire.segment_length_m;
        engine::fold_spring_limit(c, 4.0 * k_elo / (wire_node_mass_kg(s.wire) * wire_scale), "wire segments");
    }
    // Six edges per node (Gershgorin bound): ω² ≤ 12 k_m / m_m, k_m = (√3/2) E_m d.
    const double k_m = 0.5 * std::numbers::sqrt3 * s.membrane.youngs_modulus_pa * s.membrane.thickness_m;
    engine::fold_spring_limit(c, 12.0 * k_m / (membrane_node_mass_kg(s.membrane) * scale), "membrane edges");

    return {c.critical_s, engine::auto_time_step_fraction * c.critical_s, c.limited_by};
}

BodyCounts estimated_body_counts(const JobSpec& spec)
{
    const SpecimenSpec& s = spec.specimen;
    BodyCounts n;
    n.grains = s.grain_count;
    if (s.wire.pattern != WirePattern::none) {
        // Laid at ω R_a while the grains are poured (fill height / fill rate),
        // as the preparation paces it.
        const double laid_length_m = engine::estimated_wire_length_m(preparation_spec(spec));
        n.wire_nodes = static_cast<std::uint64_t>(std::ceil(laid_length_m / s.wire.segment_length_m)) + 1;
    }
    // Rows of a triangular mesh are l_m √3/2 apart.
    const double around = std::ceil(2.0 * std::numbers::pi * s.membrane_radius_m / s.membrane.mesh_size_m);
    const double rows = std::ceil(s.membrane_height_m / s.membrane.mesh_size_m * 2.0 / std::numbers::sqrt3) + 1.0;
    n.membrane_nodes = static_cast<std::uint64_t>(around * rows);
    return n;
}

double resolved_normal_damping_s(const JobSpec& spec)
{
    if (const auto* given = std::get_if<NormalDampingTime>(&spec.contact.normal_damping))
        return given->normal_damping_s;
    const auto& e = std::get<NormalRestitution>(spec.contact.normal_damping);
    const SpecimenSpec& s = spec.specimen;
    const double r = s.grain_radius_m;
    const double mass_kg = s.grain.density_kg_per_m3 * spec.engine.density_scale * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const double e_star = engine::effective_modulus_pa(
        s.grain.youngs_modulus_pa, s.grain.poisson_ratio, s.grain.youngs_modulus_pa, s.grain.poisson_ratio);
    return engine::hertz_damping_for_restitution_s(
        e.restitution, 0.5 * mass_kg, e.restitution_reference_speed_m_per_s, e_star, engine::effective_radius_m(r, r));
}

} // namespace wiredem::api
