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
