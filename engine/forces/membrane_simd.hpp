// The membrane's element forces eight at a time (AVX-512), with the scalar
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
/// (a multiple of 8) starting at the given ones; x is every membrane node.
struct MembraneSimdKernels {
    /// Edge forces: membrane_edge_force_n of each edge.
    void (*edges)(const Vec3* x, const std::array<std::uint32_t, 2>* edges, const double* rest_m,
        double stiffness_n_per_m, MembraneEdgeLaw law, Vec3* force_n, std::size_t count) = nullptr;
    /// Pressure forces: p/6 (b − a) × (c − a) of each triangle.
    void (*triangles)(const Vec3* x, const std::array<std::uint32_t, 3>* triangles, double pressure_pa,
        Vec3* force_n, std::size_t count) = nullptr;
    explicit operator bool() const { return edges != nullptr; }
};

/// The AVX-512 kernels when the SIMD paths run (simd_isa() is avx512), else none.
[[nodiscard]] MembraneSimdKernels simd_membrane_kernels();

} // namespace wiredem::engine
