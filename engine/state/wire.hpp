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
    /// ε_b, the strain past which a segment breaks (compute_wire_forces): the
    /// segment is removed and the chain has two free ends there; +∞: the
    /// model spec's unbreakable wire (docs/model.md, "A wire that breaks").
    double breaking_strain = std::numeric_limits<double>::infinity();
};

/// Why a segment was removed from the chain.
enum class WireBreakCause : std::uint8_t {
    strain = 0, ///< stretched past the breaking strain during a step
    cut = 1,    ///< cut between two steps (cut_wire_segment)
};

/// A segment removed from the chain, in the order it happened (one step's
/// breaks in ascending segment order). A removed segment exerts no force, its
/// two end joints bend no more (their nodes are free ends, rest angle 0) and
/// it reports strain 0; it never forms again. The spring's elastic energy is
/// dissipated by the break (docs/model.md, "A wire that breaks"); what the
/// nodes carry (their kinetic energy) stays with them.
struct WireBreak {
    std::uint32_t segment = 0;                ///< s, the segment between nodes s and s + 1
    WireBreakCause cause = WireBreakCause::strain;
    double time_s = 0.0;                      ///< State::time_s at the end of the step (or of the cut) [s]
    double strain = 0.0;                      ///< the segment's strain when it broke (≥ ε_b for a break)
    double released_energy_j = 0.0;           ///< ½ k_elo (ε l_w)², the spring energy it held [J]
    friend bool operator==(const WireBreak&, const WireBreak&) = default;
};

/// One piece of the wire between two removed segments (or the chain's ends).
struct WirePiece {
    std::uint32_t first_node = 0;             ///< its first node
    std::uint32_t nodes = 0;                  ///< its nodes (≥ 1)
    double rest_length_m = 0.0;               ///< (nodes − 1) l_w, its length as laid, unstretched [m]
    double length_m = 0.0;                    ///< its length along its nodes now [m]
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
