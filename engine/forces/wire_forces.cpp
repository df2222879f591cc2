#include "forces/wire_forces.hpp"

#include "laws/wire_bond.hpp"

#include <numbers>

namespace wiredem::engine {

void configure_wire(World& w, const WireSpec& spec)
{
    WireState& wire = w.wire;
    wire.radius_m = spec.radius_m;
    wire.segment_length_m = spec.segment_length_m;
    wire.axial_stiffness_n_per_m = wire_axial_stiffness_n_per_m(spec.youngs_modulus_pa, spec.radius_m, spec.segment_length_m);
    wire.bending_stiffness_n_m = wire_bending_stiffness_n_m(spec.youngs_modulus_pa, spec.radius_m, spec.segment_length_m);
    wire.node_mass_kg = spec.density_scale * spec.density_kg_per_m3 * std::numbers::pi * spec.radius_m * spec.radius_m
                      * spec.segment_length_m;
    wire.material = add_material(w, Material{spec.youngs_modulus_pa, spec.poisson_ratio, spec.density_kg_per_m3});
}

std::uint32_t append_wire_node(World& w, const Vec3& position_m, const Vec3& velocity_m_per_s)
{
    WireState& wire = w.wire;
    const std::uint32_t id = add_node(w, BodyKind::wire, position_m, wire.radius_m, wire.node_mass_kg, wire.material,
        velocity_m_per_s);
    const std::size_t nodes = id + 1;
    wire.node_force_n.resize(nodes, Vec3::Zero());
    if (nodes >= 2) {
        wire.segment_force_n.resize(nodes - 1, Vec3::Zero());
        wire.segment_strain.resize(nodes - 1, 0.0);
    }
    wire.bending_force_n.resize(nodes, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
    return id;
}

void compute_wire_forces(World& w, ThreadPool& pool)
{
    WireState& wire = w.wire;
    const auto& x = w.of(BodyKind::wire).x[0];
    const std::size_t nodes = x.size();
    if (nodes < 2) {
        if (nodes == 1) wire.node_force_n[0].setZero();
        return;
    }
    const double k = wire.axial_stiffness_n_per_m, l0 = wire.segment_length_m, k_rot = wire.bending_stiffness_n_m;
    parallel_for(pool, nodes - 1, [&](std::size_t s) {
        wire.segment_force_n[s] = wire_stretch_force_n(x[s], x[s + 1], l0, k);
        wire.segment_strain[s] = ((x[s + 1] - x[s]).norm() - l0) / l0;
    });
    parallel_for(pool, nodes, [&](std::size_t i) {
        if (i == 0 || i + 1 == nodes) return; // ends are free: no bending spring
        wire.bending_force_n[i] = wire_bending_forces_n(x[i - 1], x[i], x[i + 1], k_rot);
    });
    // Gather in a fixed order: segments i−1 and i, then the bending couples of
    // nodes i−1, i and i+1.
    parallel_for(pool, nodes, [&](std::size_t i) {
        Vec3 f = Vec3::Zero();
        if (i > 0) f -= wire.segment_force_n[i - 1];
        if (i + 1 < nodes) f += wire.segment_force_n[i];
        if (i >= 2) f += wire.bending_force_n[i - 1][2];
        if (i >= 1 && i + 1 < nodes) f += wire.bending_force_n[i][1];
        if (i + 2 < nodes) f += wire.bending_force_n[i + 1][0];
        wire.node_force_n[i] = f;
    });
}

double wire_length_m(const World& w)
{
    const auto& x = w.of(BodyKind::wire).x[0];
    double len = 0.0;
    for (std::size_t s = 0; s + 1 < x.size(); ++s) len += (x[s + 1] - x[s]).norm();
    return len;
}

} // namespace wiredem::engine
