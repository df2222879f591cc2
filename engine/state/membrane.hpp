// The membrane: a cylindrical triangular mesh of nodes (bodies of kind
// membrane) with a spring on every edge and the confining pressure on every
// triangle (the model spec §3).
#pragma once

#include "core/types.hpp"
#include "state/membrane_edge_law.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace wiredem::engine {

/// The membrane as a triangle mesh over the membrane nodes (bodies of kind
/// membrane, State): its parameters, topology, rest lengths and pressure. What
/// each step writes is Caches::membrane_forces.
///
/// The mesh is a grid: node r·columns + c is row r (z = base + r Δz), column
/// c; odd rows are turned by half a column. Node (r, c) owns
/// * the edge `along` its row to (r, c+1), in the rows between the rims (two
///   rim nodes are both fixed: a spring between them never acts);
/// * below the top row, the edges `up` to the two nearest nodes of row r+1,
///   first the one of lower column: (r+1, c−1) and (r+1, c) when r is even,
///   (r+1, c) and (r+1, c+1) when r is odd;
/// * below the top row, the two triangles of the quad between columns c and
///   c+1 of rows r and r+1 (membrane_triangle).
/// Columns wrap around. `edges` and `triangles` list them in that order, one
/// block per kind of element, row after row (membrane_edge_index,
/// membrane_triangle_index): compute_membrane_forces walks the grid, and the
/// lists serve what reads the elements one by one (energy, volume, results).
struct MembraneMesh {
    double radius_m = 0.0;                  ///< R of the undeformed cylinder [m]
    double height_m = 0.0;                  ///< H_m [m]
    double base_z_m = 0.0;                  ///< z of the bottom row [m]
    double edge_stiffness_n_per_m = 0.0;    ///< k_m = (√3/2) E_m d
    MembraneEdgeLaw edge_law = MembraneEdgeLaw::tension_only;
    double node_area_m2 = 0.0;              ///< membrane area per node, (√3/2) l_m² [m²]
    double pressure_pa = 0.0;               ///< σ₃, acting inward on every triangle [Pa]
    bool rigid = true;                      ///< rigid: nodes are not integrated
    std::size_t columns = 0;                ///< nodes per row
    std::size_t rows = 0;

    std::vector<std::array<std::uint32_t, 2>> edges; ///< (owner, other), in grid order
    std::vector<double> edge_rest_m;
    std::vector<std::array<std::uint32_t, 3>> triangles; ///< (b−a)×(c−a) points inwards, in grid order
    std::vector<std::uint8_t> node_fixed;   ///< 1 on the top and bottom rows
    std::vector<double> node_mass_kg;       ///< mass each node gets when deformable
};

/// The edges a node owns (MembraneMesh).
enum class MembraneEdge : std::uint8_t { along, up_first, up_second };

/// Edges of a grid: `along` in the rows 1 … rows−2, both `up` in rows 0 … rows−2.
[[nodiscard]] inline std::size_t membrane_edge_count(std::size_t rows, std::size_t columns) noexcept
{
    return (rows - 2) * columns + 2 * (rows - 1) * columns;
}

/// Index in MembraneMesh::edges of the edge of kind `kind` that node (row,
/// column) owns: the `along` edges of rows 1 … rows−2, then the `up_first`
/// and the `up_second` edges of rows 0 … rows−2, each row by row.
[[nodiscard]] inline std::size_t membrane_edge_index(
    std::size_t rows, std::size_t columns, MembraneEdge kind, std::size_t row, std::size_t column) noexcept
{
    const std::size_t along = (rows - 2) * columns, up = (rows - 1) * columns;
    switch (kind) {
    case MembraneEdge::along: return (row - 1) * columns + column;
    case MembraneEdge::up_first: return along + row * columns + column;
    case MembraneEdge::up_second: return along + up + row * columns + column;
    }
    return 0;
}

/// Column in row r+1 of the other end of node (r, c)'s `up` edge (`second`:
/// up_second), before wrapping: c − 1 or c on an even row, c or c + 1 on an odd one.
[[nodiscard]] inline std::ptrdiff_t membrane_up_column(std::size_t row, std::ptrdiff_t column, bool second) noexcept
{
    return column + (row % 2 == 1 ? 0 : -1) + (second ? 1 : 0);
}

/// Triangles of a grid: two per node of rows 0 … rows−2.
[[nodiscard]] inline std::size_t membrane_triangle_count(std::size_t rows, std::size_t columns) noexcept
{
    return 2 * (rows - 1) * columns;
}

/// Index in MembraneMesh::triangles of triangle `which` (0 or 1) of the quad
/// of node (row, column), row < rows − 1: all first triangles, then all second.
[[nodiscard]] inline std::size_t membrane_triangle_index(
    std::size_t rows, std::size_t columns, int which, std::size_t row, std::size_t column) noexcept
{
    return static_cast<std::size_t>(which) * (rows - 1) * columns + row * columns + column;
}

/// Corners of triangle `which` (0 or 1) of the quad of node (row, column), as
/// (row offset, column offset) pairs, ordered so that (b−a)×(c−a) points to
/// the axis: on an even row (r,c) (r+1,c) (r,c+1) and (r,c+1) (r+1,c)
/// (r+1,c+1); on an odd row (r,c) (r+1,c+1) (r,c+1) and (r,c) (r+1,c) (r+1,c+1).
[[nodiscard]] inline std::array<std::array<int, 2>, 3> membrane_triangle(std::size_t row, int which) noexcept
{
    if (row % 2 == 0)
        return which == 0 ? std::array<std::array<int, 2>, 3>{{{0, 0}, {1, 0}, {0, 1}}}
                          : std::array<std::array<int, 2>, 3>{{{0, 1}, {1, 0}, {1, 1}}};
    return which == 0 ? std::array<std::array<int, 2>, 3>{{{0, 0}, {1, 1}, {0, 1}}}
                      : std::array<std::array<int, 2>, 3>{{{0, 0}, {1, 0}, {1, 1}}};
}

/// What compute_membrane_forces writes every step before anything reads it.
/// Sized with the mesh (build_membrane).
struct MembraneForces {
    std::vector<Vec3> node_force_n;         ///< edge springs and pressure on each node [N]
};

} // namespace wiredem::engine
