// The membrane: a cylindrical triangular mesh of nodes (bodies of kind
// membrane) with a spring on every edge and the confining pressure on every
// triangle (the model spec §3).
#pragma once

#include "core/types.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace wiredem::engine {

/// How a membrane edge responds when it is shorter than its rest length.
enum class MembraneEdgeLaw : std::uint8_t {
    /// A thin sheet wrinkles rather than carry compression: an edge pulls when
    /// stretched and is slack when shorter than its rest length. The default:
    /// with linear edges the contracted membrane holds up part of σ₃ by hoop
    /// compression, and the grains feel less than the applied pressure
    /// (docs/model.md, "The membrane carries no compression").
    tension_only,
    /// The model spec §3 as written: a linear spring in tension and compression.
    linear,
};

/// The membrane as a triangle mesh over the membrane nodes (bodies of kind
/// membrane, State): its parameters, topology, rest lengths and pressure. What
/// each step writes is Caches::membrane_forces.
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

    std::vector<std::array<std::uint32_t, 2>> edges;
    std::vector<double> edge_rest_m;
    std::vector<std::array<std::uint32_t, 3>> triangles; ///< (b−a)×(c−a) points inwards
    std::vector<std::uint8_t> node_fixed;   ///< 1 on the top and bottom rows
    std::vector<double> node_mass_kg;       ///< mass each node gets when deformable

    /// Node → (edge, sign) and node → triangle incidence, CSR, ascending element id.
    std::vector<std::uint32_t> edge_incidence_start, edge_incidence;      ///< edge*2 + (node is second)
    std::vector<std::uint32_t> triangle_incidence_start, triangle_incidence;
};

/// What compute_membrane_forces writes every step before anything reads it.
/// Sized with the mesh (build_membrane).
struct MembraneForces {
    std::vector<Vec3> edge_force_n;         ///< force of edge e on its first node
    std::vector<Vec3> triangle_force_n;     ///< σ₃ A n_in / 3, on each of its nodes
    std::vector<Vec3> node_force_n;         ///< membrane forces gathered per node
};

} // namespace wiredem::engine
