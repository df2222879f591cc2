// The membrane's element forces eight (AVX-512) or four (AVX2) at a time, with the scalar
// code's operations in its order: the same bits (compiled with
// -ffp-contract=off, like contact/pair_kernel_simd.cpp, which says why).
#pragma once

#include "core/types.hpp"
#include "state/membrane.hpp"

#include <array>
#include <cstddef>
#include <cstdint>

namespace wiredem::engine {

/// The kernels of compute_membrane_forces for `count` consecutive elements
/// (a multiple of `lanes`) starting at the given ones; x is every membrane node.
struct MembraneSimdKernels {
    std::size_t lanes = 0;
    /// Edge forces: membrane_edge_force_n of each edge.
    void (*edges)(const Vec3* x, const std::array<std::uint32_t, 2>* edges, const double* rest_m,
        double stiffness_n_per_m, MembraneEdgeLaw law, Vec3* force_n, std::size_t count) = nullptr;
    /// Pressure forces: p/6 (b − a) × (c − a) of each triangle.
    void (*triangles)(const Vec3* x, const std::array<std::uint32_t, 3>* triangles, double pressure_pa,
        Vec3* force_n, std::size_t count) = nullptr;
    explicit operator bool() const { return edges != nullptr; }
};

/// The kernels of the instruction set in use (simd_isa), or none.
[[nodiscard]] MembraneSimdKernels simd_membrane_kernels();

} // namespace wiredem::engine
