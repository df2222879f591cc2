// The wire's segments and joints eight (AVX-512) or four (AVX2) at a time, with the scalar
// laws' operations in their order (laws/wire_bond.hpp; compiled with
// -ffp-contract=off, like contact/pair_kernel_simd.cpp, which says why): the
// same bits as compute_wire_forces' scalar path, the joint's angle ζ
// included (bend_angle_rad: a polynomial, not std::atan2).
#pragma once

#include "core/types.hpp"
#include "laws/wire_bond.hpp"

#include <array>
#include <cstddef>

namespace wiredem::engine {

/// The wire's constants as the kernels use them (compute_wire_forces).
struct WireKernelParams {
    double axial_stiffness_n_per_m = 0.0;  ///< k_elo
    double segment_length_m = 0.0;         ///< l₀
    double bending_stiffness_n_m = 0.0;    ///< k_rot
    double bending_yield_angle_rad = 0.0;  ///< ζ_y (+∞: elastic)
    double tau_per_dt = 0.0;               ///< Kelvin–Voigt τ/δt; 0: no dashpots
};

/// The kernels of compute_wire_forces for `count` consecutive elements (a
/// multiple of `lanes`).
struct WireSimdKernels {
    std::size_t lanes = 0;
    /// Segments s = 0 … count−1 from x[s], x[s+1] (and dx, δt × velocity):
    /// wire_segment into segment[s], the spring with its dashpot into
    /// force_n[s] (on node s), the strain (|d| − l₀)/l₀ into strain[s].
    void (*segments)(const Vec3* x, const Vec3* dx, const WireKernelParams& p, WireSegment* segment, Vec3* force_n,
        double* strain, std::size_t count) = nullptr;
    /// Joints j = 0 … count−1 between segment[j] and segment[j+1], at the
    /// node whose neighbours move by dx[j], dx[j+1], dx[j+2]: wire_joint
    /// with the rest angle rest_angle_rad[j] (updated), its dashpot, the
    /// forces on the three nodes into force_n[0][j], force_n[1][j], force_n[2][j].
    void (*joints)(const WireSegment* segment, const Vec3* dx, const WireKernelParams& p, double* rest_angle_rad,
        const std::array<Vec3*, 3>& force_n, std::size_t count) = nullptr;
    /// Nodes i = 0 … count−1 with both segments and all three joints:
    /// 0 − segment[i−1] + segment[i] + on_next[i−1] + on_node[i] + on_previous[i+1].
    void (*nodes)(const Vec3* segment_force_n, const std::array<const Vec3*, 3>& bending_force_n, Vec3* out,
        std::size_t count) = nullptr;
    explicit operator bool() const { return segments != nullptr; }
};

/// The kernels of the instruction set in use (simd_isa), or none.
[[nodiscard]] WireSimdKernels simd_wire_kernels();

} // namespace wiredem::engine
