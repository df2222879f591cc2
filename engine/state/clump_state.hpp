// Rigid multi-sphere grains (clumps): one rigid body per clump, its spheres
// grains of Motion::clumped (state/body_state.hpp). The spheres keep every
// grain array (position, velocity, spin, radius, material), so the contact
// pipeline, the walls and the outputs treat them as grains; they carry no
// mass of their own (mass, inverse mass and inverse inertia 0, so nothing
// integrates them and gravity acts on the clump, not on them). Each step the
// integrators (integrate/clumps.hpp) sum the spheres' forces and torques on
// their clump, advance it with its full inertia tensor (Euler's equations in
// the body frame) and put the spheres where the clump is, with its velocity
// at their centres and its spin. docs/model.md, "Clumps".
//
// Invariants: a clump's spheres are consecutive grains [first_member,
// first_member + member_count); member_clump and member_offset_m have one
// entry per grain once a clump exists (none and zero for a free grain), and
// are empty otherwise, so that a World without clumps holds, hashes and
// saves exactly what it did before clumps existed.
#pragma once

#include "core/types.hpp"
#include "state/body_state.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace wiredem::engine {

/// The clumps of a World (state: their motion; model: their mass properties
/// and which grains are their spheres).
struct ClumpState {
    static constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

    /// Gear-5 scaled derivatives of the centre of mass, as TranslationalState::x [m].
    std::array<std::vector<Vec3>, gear_order> x;
    /// Scaled derivatives of the angular velocity in the body frame ω_b:
    /// omega[1] = δt ω_b, omega[k] = δt^k/k! d^{k−1}ω_b/dt^{k−1} (omega[0] is
    /// not integrated and stays zero, as a grain's θ₀). With Verlet, omega[2]
    /// is δt²/2 I⁻¹ τ_b, the last half kick (no gyroscopic term).
    std::array<std::vector<Vec3>, gear_order> omega;
    std::vector<Quat> orientation;                ///< body → space, unit quaternion
    std::vector<double> mass_kg;                  ///< M [kg]
    std::vector<Vec3> principal_inertia_kg_m2;    ///< (I₁, I₂, I₃) about the body axes [kg·m²]
    std::vector<std::uint32_t> first_member;      ///< grain id of its first sphere
    std::vector<std::uint32_t> member_count;      ///< number of spheres
    /// Per grain (empty without clumps): the clump it belongs to, or none.
    std::vector<std::uint32_t> member_clump;
    /// Per grain (empty without clumps): its centre in its clump's body frame [m].
    std::vector<Vec3> member_offset_m;

    [[nodiscard]] std::size_t size() const { return mass_kg.size(); }
    [[nodiscard]] bool empty() const { return mass_kg.empty(); }
    /// Whether grain i is a sphere of a clump.
    [[nodiscard]] bool is_member(std::size_t grain) const
    {
        return grain < member_clump.size() && member_clump[grain] != none;
    }
};

/// What a step computes on the clumps (outputs, written before they are read).
struct ClumpLoads {
    std::vector<Vec3> force_n;     ///< total force, gravity included [N]
    std::vector<Vec3> torque_n_m;  ///< total torque about the centre of mass, space frame [N·m]
    /// Gear-5: the predicted orientation the spheres were put at this step
    /// (the lever arms of the forces); scratch, not state.
    std::vector<Quat> predicted_orientation;
    /// Per clump sphere (indexed by grain id, sized by the integrators'
    /// clump passes): its lever arm q b_i at the orientation the spheres were
    /// last put at in this step (place_clump_spheres), which the step's second
    /// half takes instead of turning b_i again (the same bits); scratch, not
    /// state, neither saved nor hashed.
    std::vector<Vec3> member_arm_m;
};

} // namespace wiredem::engine
