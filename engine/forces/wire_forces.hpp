// The wire's own forces: stretch of every segment and bending at every
// interior node, computed per element and gathered per node in chain order.
//
// Plastic joints. Each interior joint is an elastic–perfectly-plastic hinge,
// E = ½ k_rot (ζ − ζ₀)², whose rest angle ζ₀ (State::wire_rest_angle_rad) yields
// when |ζ − ζ₀| exceeds ζ_y (engine/laws/wire_bond.hpp). Each joint's ζ₀ is
// updated in the same parallel pass that computes its forces, by the one task
// that owns the joint, so the update is thread-count independent. The work
// done on yielding is dissipated (not counted anywhere).
//
// Material damping. The wire is a Kelvin–Voigt solid: every elastic force has
// a dashpot in parallel with the same retardation time τ,
//     F_seg = k_elo (Δl + τ dΔl/dt),   bending moment k_rot (ζ − ζ₀ + τ dζ/dt),
// the bending dashpot applied as −τ k_rot ζ̇ ∇ζ (the gradient of the Rayleigh
// function ½ τ k_rot ζ̇²), so, like the springs, it exerts no net force and
// no net torque and a rigidly moving wire feels nothing. τ is fixed by the
// damping ratio of the chain's highest (axial) mode, τ = 2 ξ_w / ω_max with
// ω_max² = 4 k_elo/m_w (docs/model.md, "Wire"); a mode of frequency ω then
// has the damping ratio ω τ / 2. This is damping inside the wire, not global
// viscous damping: it dissipates only relative motion of neighbouring nodes.
#pragma once

#include "forces/wire_material.hpp"
#include "parallel/thread_pool.hpp"
#include "state/world.hpp"

#include <cstdint>
#include <limits>
#include <vector>

namespace wiredem::engine {

/// Wire parameters (the model spec §2); masses are multiplied by density_scale.
/// The material as a job gives it (WireMaterial, wire_material.hpp), then
/// what the job derives: the mass scaling and the wire's two strains as
/// numbers.
struct WireSpec : WireMaterial {
    double density_scale = 1.0;
    /// ε_y = σ_y/E_w, the wire's yield strain in bending; the joints are
    /// elastic–perfectly-plastic hinges with ζ_y = ε_y l_w / r_w (docs/model.md,
    /// "Wire"); +∞ is the specification's elastic wire (straight rest state).
    double bending_yield_strain = default_bending_yield_strain;
    /// ε_b, the strain past which a segment breaks (WireChain::breaking_strain),
    /// > 0; +∞: unbreakable, the model spec's wire.
    double breaking_strain = std::numeric_limits<double>::infinity();
};

/// Damping ratio ξ_w of the wire's highest axial mode (Kelvin–Voigt material
/// damping, see the file comment). Its highest bending mode then has
/// ξ_w r_w / l_w (0.4 ξ_w with the paper's wire); long, slow bending waves
/// much less. 0.3 damps the short waves that a joint laid along a curve
/// releases (it stores ½ k_rot ζ² per node, the model spec §3) without
/// slowing the wire's quasi-static response; 1.0 made Gear-5 at the auto
/// time step blow up (measured on examples/small.json).
inline constexpr double wire_damping_ratio = 0.3;

/// Kelvin–Voigt retardation time τ = 2 ξ_w / ω_max, ω_max² = 4 k_elo/m_w [s];
/// 0 for a wire without mass or stiffness.
[[nodiscard]] double wire_retardation_time_s(const WireChain& wire);

/// Sets the wire's parameters (material, stiffnesses, node mass). Call before
/// adding nodes.
void configure_wire(World& w, const WireSpec& spec);

/// Appends a node at the end of the chain (linked to the previous node, if
/// any) moving with `velocity_m_per_s`; returns its index. The chain can grow
/// during a run: only the new node's slots are added.
std::uint32_t append_wire_node(World& w, const Vec3& position_m, const Vec3& velocity_m_per_s = Vec3::Zero());

/// Stage: stretch and bending forces (springs and their dashpots) into
/// per-element slots, then per node. Also refreshes WireForces::segment_strain
/// and lets the joints' rest angles yield (State::wire_rest_angle_rad; calling it
/// twice at the same positions changes nothing more).
/// Velocities are the integrator's current ones (x[1] / δt).
///
/// Breaking (docs/model.md, "A wire that breaks"): a removed segment
/// (State::wire_breaks) exerts nothing, and neither do the joints at its two
/// ends; when the wire is breakable, every other segment whose strain exceeds
/// ε_b now breaks, in ascending order, recorded in State::wire_breaks at the
/// time the step ends (time_s + δt) and removed from this step's forces on.
/// The check is serial over the segments; an unbreakable, whole wire skips it
/// and computes what it always did.
void compute_wire_forces(World& w, ThreadPool& pool);

/// Cuts segment `segment` (between nodes segment and segment + 1) between two
/// steps: recorded in State::wire_breaks as a cut at time_s with the strain
/// and spring energy it held. The next step computes the forces without it;
/// the last step's outputs (forces, strains) stay as they were.
/// @return false, changing nothing, when the wire has no such segment or it
///         is removed already
bool cut_wire_segment(World& w, std::uint32_t segment);

/// Whether each segment is removed (1) or whole (0), by segment index.
[[nodiscard]] std::vector<std::uint8_t> removed_wire_segments(const State& s);

/// The pieces of the wire between its removed segments, in chain order (one
/// piece, the whole chain, when none is removed; none without nodes).
[[nodiscard]] std::vector<WirePiece> wire_pieces(const World& w);

/// The position along the wire of the middle of segment `segment`, as the
/// rest length from the first node: (segment + ½) l_w [m]. Cuts are asked
/// for and breaks reported at such positions.
[[nodiscard]] inline double wire_segment_position_m(const WireChain& wire, std::uint32_t segment)
{
    return (static_cast<double>(segment) + 0.5) * wire.segment_length_m;
}

/// Total length of the wire along its nodes [m], its removed segments left out.
[[nodiscard]] double wire_length_m(const World& w);

} // namespace wiredem::engine
