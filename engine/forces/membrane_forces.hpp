// The membrane's own forces: edge springs and the confining pressure, per
// element then summed per node in a fixed order; plus the load of the
// specimen (grains and wire) on the membrane, which the triaxial test reads as
// its effective confining pressure.
#pragma once

#include "forces/membrane_material.hpp"
#include "parallel/thread_pool.hpp"
#include "state/world.hpp"

namespace wiredem::engine {

/// Membrane parameters (the model spec §2–§3): the material and mesh as a
/// job gives them (MembraneMaterial, membrane_material.hpp), then the
/// cylinder's size and place and what the job derives; masses × density_scale.
struct MembraneSpec : MembraneMaterial {
    double radius_m = 20e-3;            ///< R
    double height_m = 0.12;             ///< H_m
    double base_z_m = 0.0;              ///< z of the bottom row
    double contact_radius_m = 0.5e-3;   ///< r_m, default d/2
    double density_scale = 1.0;
};

/// Meshes the cylinder: rows of `columns` nodes, alternate rows turned by half
/// a column so that the triangles are nearly equilateral; the top and bottom
/// rows are fixed. The membrane starts rigid.
void build_membrane(World& w, const MembraneSpec& spec);

/// The grid's edges (owner, other) and its triangles, in the order of
/// state/membrane.hpp.
[[nodiscard]] std::vector<std::array<std::uint32_t, 2>> membrane_grid_edges(std::size_t rows, std::size_t columns);
[[nodiscard]] std::vector<std::array<std::uint32_t, 3>> membrane_grid_triangles(std::size_t rows, std::size_t columns);

/// Rigid (nodes held, contact forces still computed) or deformable (all but
/// the top and bottom rows integrated).
void set_membrane_rigid(World& w, bool rigid);

/// Stage: edge springs and pressure σ₃ A n_in / 3 per triangle, summed per
/// node. Walks the grid row by row: each row's elements, then its nodes'
/// sums, so that a row's forces are still in cache when its nodes read them.
void compute_membrane_forces(World& w, ThreadPool& pool);

/// What the grains do to the membrane this step.
struct MembraneLoad {
    double normal_force_n = 0.0;        ///< Σ |F_n| over grain– and wire–membrane contacts [N]
    double radial_force_n = 0.0;        ///< Σ outward radial component of those forces [N]
    std::size_t contacts = 0;           ///< grain– and wire–membrane contacts touching
    std::size_t nodes_in_contact = 0;   ///< membrane nodes touched by ≥ 1 grain or wire node
    double area_in_contact_m2 = 0.0;    ///< nodes_in_contact × area per node [m²]
};

/// Sums the grain– and wire–membrane contacts of the current step, deterministically.
[[nodiscard]] MembraneLoad membrane_contact_load(const World& w, ThreadPool& pool);

/// Volume enclosed by the membrane between its rims [m³] (sum over triangles
/// of the signed tetrahedra to the axis, closed by the flat rims).
[[nodiscard]] double membrane_volume_m3(const World& w);

} // namespace wiredem::engine
