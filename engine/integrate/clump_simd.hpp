// The clumps' per-clump passes that run in SIMD lanes where the CPU has them
// (integrate/clump_simd.cpp, clump_lanes.inc): the turn of the orientations
// and the placement of the spheres, several clumps per instruction, each
// lane with the scalar code's operations in Eigen's order (the same bits as
// with `--simd scalar`, which runs the scalar code).
#pragma once

#include "core/types.hpp"

#include <cstddef>
#include <cstdint>

namespace wiredem::engine {

/// What place_clumps reads and writes: the clumps' arrays (indexed by clump)
/// and the grains' (indexed by grain id).
struct ClumpPlacement {
    const Quat* orientation;           ///< q of each clump, body → space
    const Vec3* centre;                ///< x₀ of each clump [m]
    const Vec3* velocity;              ///< x₁ = δt v of each clump [m]
    const Vec3* omega1;                ///< w₁ = δt ω_b of each clump, body frame
    const std::uint32_t* first_member; ///< grain id of each clump's first sphere
    const std::uint32_t* member_count; ///< spheres of each clump
    const Vec3* offset;                ///< each sphere's centre in its clump's body frame [m]
    const Vec3* arms_in;               ///< the lever arms q b to take (null: turn the offsets)
    Vec3* arms_out;                    ///< where to write the lever arms (null: nowhere)
    Vec3* x0;                          ///< the grains' positions [m]
    Vec3* x1;                          ///< the grains' δt v [m]
    Vec3* theta1;                      ///< the grains' δt ω
};

/// What sum_clump_loads reads and writes: the grains' loads and lever arms
/// (indexed by grain id) and the clumps' masses and loads.
struct ClumpLoadSums {
    const Vec3* force;                 ///< the grains' forces [N]
    const Vec3* torque;                ///< the grains' torques [N·m]
    const Vec3* arms;                  ///< the lever arms q b (null: turn the offsets by `orientation`)
    const Vec3* offset;                ///< each sphere's centre in its clump's body frame [m]
    const Quat* orientation;           ///< q of each clump the arms are at
    const std::uint32_t* first_member; ///< grain id of each clump's first sphere
    const std::uint32_t* member_count; ///< spheres of each clump
    const double* mass;                ///< M of each clump [kg]
    Vec3 gravity;                      ///< g [m/s²]
    bool gravity_acts;                 ///< whether M g is added
    Vec3* force_out;                   ///< each clump's force [N]
    Vec3* torque_out;                  ///< each clump's torque about its centre of mass [N·m]
};

/// Clump i's loads: F = M g + Σ f_m, τ = Σ (q b_m) × f_m + τ_m, in sphere
/// order, into s.force_out[i] and s.torque_out[i].
void sum_clump_loads(const ClumpLoadSums& s, std::size_t i);

/// What the kicks of clump_kicks take besides the loads.
struct ClumpKick {
    const Quat* orientation;           ///< q the torque is turned into the body frame by
    const Vec3* inertia;               ///< principal moments (I₁, I₂, I₃) [kg·m²]
    const Vec3* omega1;                ///< w₁ = δt ω_b (for the gyroscopic term)
    double half_dt2;                   ///< δt²/2 [s²]
    bool gyroscopic;                   ///< Gear-5: minus ½ I⁻¹ (w₁ × I w₁)
};

/// For clumps [b, e): their loads (sum_clump_loads), δt²/2 F/M into
/// x2[i − b] and δt²/2 I⁻¹ q⁻¹ τ (minus ½ I⁻¹ (w₁ × I w₁) with
/// k.gyroscopic) into w2[i − b].
void clump_kicks(const ClumpLoadSums& s, const ClumpKick& k, std::size_t b, std::size_t e, Vec3* x2, Vec3* w2);

/// The rotation vector of a Gear-5 step from the scaled derivatives
/// w₁ … w₅ of clumps [b, e), into turn[i − b]: forwards from t
/// (w₁ + w₂ + w₃ + w₄ + w₅, the prediction) or backwards from t + δt
/// (w₁ − w₂ + w₃ − w₄ + w₅, the correction), plus the Magnus term (w₁ × w₂)/6.
void gear_turns(const Vec3* const* w, bool forwards, std::size_t b, std::size_t e, Vec3* turn);

/// out[i] = (q[i] ⊗ rotation_quaternion(theta[i])).normalized() for i in
/// [0, n) (out may be q).
void turn_clumps(const Quat* q, const Vec3* theta, Quat* out, std::size_t n);

/// The free rotation of one step of a clump with principal inertia `inertia`,
/// orientation q and w₁ = δt ω_b (Verlet's drift; the description at its
/// definition, clump_simd.cpp).
void free_rotation(Quat& q, Vec3& w1, const Vec3& inertia);

/// free_rotation(q[i], w1[i], inertia[i]) for i in [0, n).
void free_rotations(Quat* q, Vec3* w1, const Vec3* inertia, std::size_t n);

/// place_clump_spheres (or, with arms_in, place_clump_spheres_at_arms) of
/// clumps [b, e) at p.orientation (state/world.hpp), the lever arms also
/// into p.arms_out when it is set.
void place_clumps(const ClumpPlacement& p, std::size_t b, std::size_t e);

} // namespace wiredem::engine
