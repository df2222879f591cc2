// The wire: one chain of nodes (bodies of kind wire). Node i is the i-th node
// laid, so chain order is id order and segment s joins nodes s and s+1.
#pragma once

#include "core/types.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace wiredem::engine {

/// The wire's model (the model spec §2): the parameters every node and
/// segment shares. The nodes themselves are bodies of kind wire (State); the
/// joints' rest angles are State::wire_rest_angle_rad; what each step writes
/// is Caches::wire_forces.
struct WireChain {
    double radius_m = 0.5e-3;               ///< r_w, contact sphere radius [m]
    double segment_length_m = 1.25e-3;      ///< l_w, rest length of every segment [m]
    double axial_stiffness_n_per_m = 0.0;   ///< k_elo
    double bending_stiffness_n_m = 0.0;     ///< k_rot
    /// ζ_y = ε_y l_w / r_w, the angle at which a joint yields [rad]; +∞: the
    /// specification's elastic wire (docs/model.md, "Wire").
    double bending_yield_angle_rad = std::numeric_limits<double>::infinity();
    double node_mass_kg = 0.0;              ///< ρ_w π r_w² l_w (× density scaling)
    std::uint8_t material = 0;
};

/// What compute_wire_forces writes every step before anything reads it: the
/// per-element slots (one writer each, gathered per node in chain order) and
/// the segments' strain. Sized with the chain (append_wire_node).
struct WireForces {
    std::vector<Vec3> segment_force_n;      ///< force of segment s on node s (node s+1 gets −)
    /// The bending couple of the joint at interior node i: [0][i] on node
    /// i−1, [1][i] on node i, [2][i] on node i+1 (zero at the two ends).
    std::array<std::vector<Vec3>, 3> bending_force_n;
    std::vector<Vec3> node_force_n;         ///< wire forces gathered per node
    /// Current strain of every segment, (|x_{s+1} − x_s| − l_w)/l_w.
    std::vector<double> segment_strain;
};

} // namespace wiredem::engine
