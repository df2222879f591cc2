#include "forces/wire_forces.hpp"

#include "laws/wire_bond.hpp"

#include <cmath>
#include <numbers>

namespace wiredem::engine {

namespace {

/// ∇ζ at an interior node: the gradients of the angle ζ between a = x_i − x_{i−1}
/// and b = x_{i+1} − x_i with respect to x_{i−1}, x_i, x_{i+1} [1/m]:
///   ∂ζ/∂x_{i+1} = −(â − cos ζ b̂)/(|b| sin ζ),  ∂ζ/∂x_{i−1} = (b̂ − cos ζ â)/(|a| sin ζ),
///   ∂ζ/∂x_i = −(∂ζ/∂x_{i−1} + ∂ζ/∂x_{i+1})
/// (each of length 1/|b|, 1/|a|: bounded). Zero for a straight or degenerate
/// joint, where the bending direction is undefined.
std::array<Vec3, 3> bend_angle_gradient_per_m(const Vec3& x_prev, const Vec3& x, const Vec3& x_next)
{
    const Vec3 a = x - x_prev, b = x_next - x;
    const double la = a.norm(), lb = b.norm();
    if (la == 0.0 || lb == 0.0) return {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    const Vec3 ua = a / la, ub = b / lb;
    const double cos_z = ua.dot(ub), sin_z = ua.cross(ub).norm();
    if (sin_z < 1e-9) return {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    const Vec3 g_next = -(ua - cos_z * ub) / (lb * sin_z);
    const Vec3 g_prev = (ub - cos_z * ua) / (la * sin_z);
    return {g_prev, -(g_prev + g_next), g_next};
}

} // namespace

double wire_retardation_time_s(const WireState& wire)
{
    if (!(wire.node_mass_kg > 0.0) || !(wire.axial_stiffness_n_per_m > 0.0)) return 0.0;
    return 2.0 * wire_damping_ratio / std::sqrt(4.0 * wire.axial_stiffness_n_per_m / wire.node_mass_kg);
}

void configure_wire(World& w, const WireSpec& spec)
{
    WireState& wire = w.wire;
    wire.radius_m = spec.radius_m;
    wire.segment_length_m = spec.segment_length_m;
    wire.axial_stiffness_n_per_m = wire_axial_stiffness_n_per_m(spec.youngs_modulus_pa, spec.radius_m, spec.segment_length_m);
    wire.bending_stiffness_n_m = wire_bending_stiffness_n_m(spec.youngs_modulus_pa, spec.radius_m, spec.segment_length_m);
    wire.bending_yield_angle_rad = wire_bending_yield_angle_rad(spec.bending_yield_strain, spec.radius_m, spec.segment_length_m);
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
    wire.rest_angle_rad.resize(nodes, 0.0); // the new joint starts straight and yields as it is laid
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
    const auto& dx = w.of(BodyKind::wire).x[1]; // δt · velocity
    const std::size_t nodes = x.size();
    if (nodes < 2) {
        if (nodes == 1) wire.node_force_n[0].setZero();
        return;
    }
    const double k = wire.axial_stiffness_n_per_m, l0 = wire.segment_length_m, k_rot = wire.bending_stiffness_n_m;
    const double zeta_y = wire.bending_yield_angle_rad;
    // Dashpots: τ k (dΔl/dt) and τ k_rot ζ̇, with velocities x[1]/δt.
    const double tau_per_dt = wire_retardation_time_s(wire) / w.dt_s;
    parallel_for(pool, nodes - 1, [&](std::size_t s) {
        const Vec3 d = x[s + 1] - x[s];
        const double len = d.norm();
        Vec3 f = wire_stretch_force_n(x[s], x[s + 1], l0, k);
        if (len > 0.0 && tau_per_dt > 0.0) {
            const Vec3 u = d / len;
            f += (tau_per_dt * k * (dx[s + 1] - dx[s]).dot(u)) * u; // resists the rate of extension
        }
        wire.segment_force_n[s] = f;
        wire.segment_strain[s] = (len - l0) / l0;
    });
    parallel_for(pool, nodes, [&](std::size_t i) {
        if (i == 0 || i + 1 == nodes) return; // ends are free: no bending spring
        // The joint yields, then pushes back elastically; only this task writes ζ₀[i].
        const WireJoint joint = wire_joint(x[i - 1], x[i], x[i + 1], k_rot, wire.rest_angle_rad[i], zeta_y);
        wire.rest_angle_rad[i] = joint.rest_angle_rad;
        std::array<Vec3, 3> f = joint.force_n;
        if (tau_per_dt > 0.0) {
            const auto g = bend_angle_gradient_per_m(x[i - 1], x[i], x[i + 1]);
            const double zeta_dot_dt = g[0].dot(dx[i - 1]) + g[1].dot(dx[i]) + g[2].dot(dx[i + 1]); // δt · ζ̇
            const double c = tau_per_dt * k_rot * zeta_dot_dt;
            for (int j = 0; j < 3; ++j) f[j] -= c * g[j];
        }
        wire.bending_force_n[i] = f;
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
