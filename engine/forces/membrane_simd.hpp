// The membrane's row kernels eight (AVX-512) or four (AVX2) columns at a
// time, with the scalar code's operations in its order: the same bits
// (compiled with -ffp-contract=off, like contact/pair_kernel_simd.cpp, which
// says why).
#pragma once

#include "state/membrane.hpp"

#include <cstddef>

namespace wiredem::engine {

/// One row of the grid, one array per component: column c at x()[c],
/// y()[c], z()[c], the components `stride` doubles apart (one pointer per
/// row: a node sum reads twelve rows, more than there are registers for
/// three pointers each). compute_membrane_forces keeps its rows with a
/// column of the other end of the row on either side (c = −1 and c =
/// columns…), so that a neighbour one column away is at a fixed offset even
/// where the row wraps around.
struct MembraneRow {
    double* data = nullptr;
    std::ptrdiff_t stride = 0;
    [[nodiscard]] double* x() const { return data; }
    [[nodiscard]] double* y() const { return data + stride; }
    [[nodiscard]] double* z() const { return data + 2 * stride; }
    /// The same row `by` columns further (the neighbour's value at column c).
    [[nodiscard]] MembraneRow shifted(std::ptrdiff_t by) const { return {data + by, stride}; }
};

/// A node sums twelve element forces (six edges, six triangles): the first
/// `membrane_added_terms` added, the others subtracted, each from a row
/// shifted so that column c holds the element the node of column c takes.
inline constexpr std::size_t membrane_terms = 12, membrane_added_terms = 9;

/// The kernels of compute_membrane_forces for columns 0 … count−1 (count a
/// multiple of `lanes`); each writes out[c] from its inputs' column c.
struct MembraneSimdKernels {
    std::size_t lanes = 0;
    /// membrane_edge_force_n(a[c], b[c], rest[c], k, law): the force on a.
    void (*edges)(MembraneRow a, MembraneRow b, const double* rest_m, double stiffness_n_per_m,
        MembraneEdgeLaw law, MembraneRow out, std::size_t count) = nullptr;
    /// p/6 (b − a) × (c − a) of the triangle (a[c], b[c], c[c]).
    void (*triangles)(MembraneRow a, MembraneRow b, MembraneRow c, double pressure_pa, MembraneRow out,
        std::size_t count) = nullptr;
    /// out[c] = 0 + term[0][c] + … + term[8][c] − term[9][c] − … − term[11][c], in that order,
    /// the terms being rows of one store (`terms` their data, `stride` theirs).
    void (*sums)(const double* const* terms, std::ptrdiff_t stride, Vec3* out, std::size_t count) = nullptr;
    /// The Vec3s x[0 … count−1] into a row.
    void (*split)(const Vec3* x, MembraneRow out, std::size_t count) = nullptr;
    explicit operator bool() const { return edges != nullptr; }
};

/// The kernels of the instruction set in use (simd_isa), or none.
[[nodiscard]] MembraneSimdKernels simd_membrane_kernels();

} // namespace wiredem::engine
