#include "forces/wire_forces.hpp"

#include "forces/wire_simd.hpp"
#include "laws/wire_bond.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace wiredem::engine {

namespace {

/// Nodes per block of compute_wire_forces (its segments sit on the stack).
constexpr std::size_t wire_block = 256;

/// Takes a removed segment out of the step's slots: no spring force, strain
/// 0, and no joint at either of its ends (those nodes are free ends now,
/// with the rest angle 0 of an end).
void clear_removed_segment(WireForces& slots, std::vector<double>& rest_angle, std::size_t segment, std::size_t nodes)
{
    slots.segment_force_n[segment].setZero();
    slots.segment_strain[segment] = 0.0;
    for (std::size_t joint : {segment, segment + 1}) {
        if (joint < 1 || joint + 1 >= nodes) continue; // an end of the chain has no joint
        for (std::vector<Vec3>& on : slots.bending_force_n) on[joint].setZero();
        rest_angle[joint] = 0.0;
    }
}

/// ½ k_elo (ε l_w)², the spring energy of a segment at strain ε [J].
double spring_energy_j(const WireChain& wire, double strain)
{
    const double dl = strain * wire.segment_length_m;
    return 0.5 * wire.axial_stiffness_n_per_m * dl * dl;
}

} // namespace

double wire_retardation_time_s(const WireChain& wire)
{
    if (!(wire.node_mass_kg > 0.0) || !(wire.axial_stiffness_n_per_m > 0.0)) return 0.0;
    return 2.0 * wire_damping_ratio / std::sqrt(4.0 * wire.axial_stiffness_n_per_m / wire.node_mass_kg);
}

void configure_wire(World& w, const WireSpec& spec)
{
    WireChain& wire = w.wire;
    wire.radius_m = spec.radius_m;
    wire.segment_length_m = spec.segment_length_m;
    wire.axial_stiffness_n_per_m = wire_axial_stiffness_n_per_m(spec.youngs_modulus_pa, spec.radius_m, spec.segment_length_m);
    wire.bending_stiffness_n_m = wire_bending_stiffness_n_m(spec.youngs_modulus_pa, spec.radius_m, spec.segment_length_m);
    wire.bending_yield_angle_rad = wire_bending_yield_angle_rad(spec.bending_yield_strain, spec.radius_m, spec.segment_length_m);
    wire.breaking_strain = spec.breaking_strain;
    wire.node_mass_kg = spec.density_scale * spec.density_kg_per_m3 * std::numbers::pi * spec.radius_m * spec.radius_m
                      * spec.segment_length_m;
    wire.material = add_material(w, Material{spec.youngs_modulus_pa, spec.poisson_ratio, spec.density_kg_per_m3});
}

std::uint32_t append_wire_node(World& w, const Vec3& position_m, const Vec3& velocity_m_per_s)
{
    WireChain& wire = w.wire;
    const std::uint32_t id = add_node(w, BodyKind::wire, position_m, wire.radius_m, wire.node_mass_kg, wire.material,
        velocity_m_per_s);
    const std::size_t nodes = id + 1;
    w.wire_rest_angle_rad.resize(nodes, 0.0); // the new joint starts straight and yields as it is laid
    WireForces& slots = w.wire_forces;
    slots.node_force_n.resize(nodes, Vec3::Zero());
    if (nodes >= 2) {
        slots.segment_force_n.resize(nodes - 1, Vec3::Zero());
        slots.segment_strain.resize(nodes - 1, 0.0);
    }
    for (std::vector<Vec3>& on : slots.bending_force_n) on.resize(nodes, Vec3::Zero());
    return id;
}

void compute_wire_forces(World& w, ThreadPool& pool)
{
    const WireChain& wire = w.wire;
    WireForces& slots = w.wire_forces;
    std::vector<double>& rest_angle = w.wire_rest_angle_rad;
    const auto& x = w.of(BodyKind::wire).x[0];
    const auto& dx = w.of(BodyKind::wire).x[1]; // δt · velocity
    const std::size_t nodes = x.size();
    if (nodes < 2) {
        if (nodes == 1) slots.node_force_n[0].setZero();
        return;
    }
    const double k = wire.axial_stiffness_n_per_m, l0 = wire.segment_length_m, k_rot = wire.bending_stiffness_n_m;
    const double zeta_y = wire.bending_yield_angle_rad;
    // Dashpots: τ k (dΔl/dt) and τ k_rot ζ̇, with velocities x[1]/δt.
    const double tau_per_dt = wire_retardation_time_s(wire) / w.dt_s;
    // Block by block: a block finds the segments its joints need (one before
    // its first node, written by the block before), writes the forces and
    // strains of its own segments, then its joints'. Each segment's length and
    // direction are worked out once per block and serve the spring, its
    // dashpot and the two joints at its ends.
    const WireKernelParams params{k, l0, k_rot, zeta_y, tau_per_dt};
    // Four or eight segments and joints at a time where the CPU can (same
    // bits, forces/wire_simd.hpp); the rest one by one.
    const WireSimdKernels simd = simd_wire_kernels();
    parallel_for_blocks(pool, nodes, wire_block, [&](std::size_t begin, std::size_t end) {
        std::array<WireSegment, wire_block + 1> segment; // segment s at [s − first]
        const std::size_t first = begin == 0 ? 0 : begin - 1;
        const std::size_t segments_end = std::min(end, nodes - 1);
        if (first < begin) segment[0] = wire_segment(x[first], x[first + 1]); // the block before writes its force
        std::size_t s = begin;
        if (simd) {
            const std::size_t n = (segments_end - std::min(begin, segments_end)) / simd.lanes * simd.lanes;
            simd.segments(x.data() + s, dx.data() + s, params, segment.data() + (s - first),
                slots.segment_force_n.data() + s, slots.segment_strain.data() + s, n);
            s += n;
        }
        for (; s < segments_end; ++s) {
            const WireSegment seg = wire_segment(x[s], x[s + 1]);
            segment[s - first] = seg;
            Vec3 f = wire_stretch_force_n(x[s], x[s + 1], l0, k);
            if (seg.length_m > 0.0 && tau_per_dt > 0.0) // resists the rate of extension
                f += (tau_per_dt * k * (dx[s + 1] - dx[s]).dot(seg.unit)) * seg.unit;
            slots.segment_force_n[s] = f;
            slots.segment_strain[s] = (seg.length_m - l0) / l0;
        }
        // Interior joints only: the ends are free, with no bending spring.
        std::size_t i = std::max<std::size_t>(begin, 1);
        if (simd && i < segments_end) {
            const std::size_t n = (segments_end - i) / simd.lanes * simd.lanes;
            simd.joints(segment.data() + (i - 1 - first), dx.data() + (i - 1), params, rest_angle.data() + i,
                {slots.bending_force_n[0].data() + i, slots.bending_force_n[1].data() + i, slots.bending_force_n[2].data() + i},
                n);
            i += n;
        }
        for (; i < segments_end; ++i) {
            // The joint yields, then pushes back elastically; only this task writes ζ₀[i].
            const WireJoint joint = wire_joint(segment[i - 1 - first], segment[i - first], k_rot, rest_angle[i], zeta_y);
            rest_angle[i] = joint.rest_angle_rad;
            std::array<Vec3, 3> f = joint.force_n;
            if (tau_per_dt > 0.0) {
                const auto& g = joint.angle_gradient_per_m;
                const double zeta_dot_dt = g[0].dot(dx[i - 1]) + g[1].dot(dx[i]) + g[2].dot(dx[i + 1]); // δt · ζ̇
                const double c = tau_per_dt * k_rot * zeta_dot_dt;
                for (int j = 0; j < 3; ++j) f[j] -= c * g[j];
            }
            for (int j = 0; j < 3; ++j) slots.bending_force_n[j][i] = f[j];
        }
    });
    // Removed segments, then the ones that break now (serial, in segment
    // order: the same events for any thread count). Nothing to do for a whole,
    // unbreakable wire, which computes what it always did.
    for (const WireBreak& b : w.wire_breaks) clear_removed_segment(slots, rest_angle, b.segment, nodes);
    if (std::isfinite(wire.breaking_strain)) {
        for (std::size_t s = 0; s + 1 < nodes; ++s) {
            const double strain = slots.segment_strain[s]; // a removed segment's is 0 < ε_b
            if (!(strain > wire.breaking_strain)) continue;
            w.wire_breaks.push_back({.segment = static_cast<std::uint32_t>(s), .cause = WireBreakCause::strain,
                .time_s = w.time_s + w.dt_s, .strain = strain, .released_energy_j = spring_energy_j(wire, strain)});
            clear_removed_segment(slots, rest_angle, s, nodes);
        }
    }
    // Gather in a fixed order: segments i−1 and i, then the bending couples of
    // the joints at nodes i−1, i and i+1. Nodes 2 … nodes−3 have all five,
    // lanes at a time where the CPU can.
    const auto& bending = slots.bending_force_n;
    const auto node_sum = [&](std::size_t i) {
        Vec3 f = Vec3::Zero();
        if (i > 0) f -= slots.segment_force_n[i - 1];
        if (i + 1 < nodes) f += slots.segment_force_n[i];
        if (i >= 2) f += bending[2][i - 1];
        if (i >= 1 && i + 1 < nodes) f += bending[1][i];
        if (i + 2 < nodes) f += bending[0][i + 1];
        slots.node_force_n[i] = f;
    };
    parallel_for_blocks(pool, nodes, wire_block, [&](std::size_t begin, std::size_t end) {
        std::size_t i = begin;
        if (simd) {
            for (; i < std::min<std::size_t>(end, 2); ++i) node_sum(i);
            const std::size_t inner_end = std::min(end, nodes - 2); // nodes ≥ 2 here
            const std::size_t n = i < inner_end ? (inner_end - i) / simd.lanes * simd.lanes : 0;
            if (n > 0) simd.nodes(slots.segment_force_n.data() + i, {bending[0].data() + i, bending[1].data() + i, bending[2].data() + i}, slots.node_force_n.data() + i, n);
            i += n;
        }
        for (; i < end; ++i) node_sum(i);
    });
}

bool cut_wire_segment(World& w, std::uint32_t segment)
{
    const auto& x = w.of(BodyKind::wire).x[0];
    const std::size_t nodes = x.size();
    if (std::size_t{segment} + 1 >= nodes) return false;
    for (const WireBreak& b : w.wire_breaks)
        if (b.segment == segment) return false;
    const double strain = ((x[segment + 1] - x[segment]).norm() - w.wire.segment_length_m) / w.wire.segment_length_m;
    w.wire_breaks.push_back({.segment = segment, .cause = WireBreakCause::cut, .time_s = w.time_s, .strain = strain,
        .released_energy_j = spring_energy_j(w.wire, strain)});
    return true;
}

std::vector<std::uint8_t> removed_wire_segments(const State& s)
{
    const std::size_t nodes = s.of(BodyKind::wire).size();
    std::vector<std::uint8_t> removed(nodes > 0 ? nodes - 1 : 0, 0);
    for (const WireBreak& b : s.wire_breaks)
        if (b.segment < removed.size()) removed[b.segment] = 1;
    return removed;
}

std::vector<WirePiece> wire_pieces(const World& w)
{
    const auto& x = w.of(BodyKind::wire).x[0];
    const std::vector<std::uint8_t> removed = removed_wire_segments(w);
    std::vector<WirePiece> pieces;
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (i == 0 || removed[i - 1]) pieces.push_back({.first_node = static_cast<std::uint32_t>(i)});
        WirePiece& p = pieces.back();
        if (i > p.first_node) p.length_m += (x[i] - x[i - 1]).norm();
        ++p.nodes;
    }
    for (WirePiece& p : pieces) p.rest_length_m = static_cast<double>(p.nodes - 1) * w.wire.segment_length_m;
    return pieces;
}

double wire_length_m(const World& w)
{
    const auto& x = w.of(BodyKind::wire).x[0];
    double len = 0.0;
    if (w.wire_breaks.empty()) {
        for (std::size_t s = 0; s + 1 < x.size(); ++s) len += (x[s + 1] - x[s]).norm();
        return len;
    }
    const std::vector<std::uint8_t> removed = removed_wire_segments(w); // the gaps between pieces are no wire
    for (std::size_t s = 0; s + 1 < x.size(); ++s)
        if (removed[s] == 0) len += (x[s + 1] - x[s]).norm();
    return len;
}

} // namespace wiredem::engine
