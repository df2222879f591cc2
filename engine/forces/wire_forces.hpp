// The wire's own forces: stretch of every segment and bending at every
// interior node, computed per element and gathered per node in chain order.
#pragma once

#include "parallel/thread_pool.hpp"
#include "state/world.hpp"

namespace wiredem::engine {

/// Wire parameters (the model spec §2); masses are multiplied by density_scale.
struct WireSpec {
    double radius_m = 0.5e-3;
    double segment_length_m = 1.25e-3;
    double youngs_modulus_pa = 1e9;
    double poisson_ratio = 0.0;
    double density_kg_per_m3 = 1000.0;
    double density_scale = 1.0;
};

/// Sets the wire's parameters (material, stiffnesses, node mass). Call before
/// adding nodes.
void configure_wire(World& w, const WireSpec& spec);

/// Appends a node at the end of the chain (linked to the previous node, if
/// any) moving with `velocity_m_per_s`; returns its index. The chain can grow
/// during a run: only the new node's slots are added.
std::uint32_t append_wire_node(World& w, const Vec3& position_m, const Vec3& velocity_m_per_s = Vec3::Zero());

/// Stage: stretch and bending forces into per-element slots, then per node.
/// Also refreshes WireState::segment_strain.
void compute_wire_forces(World& w, ThreadPool& pool);

/// Total length of the wire along its nodes [m].
[[nodiscard]] double wire_length_m(const World& w);

} // namespace wiredem::engine
