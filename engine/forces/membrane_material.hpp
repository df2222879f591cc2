// The membrane's material and mesh that a job gives as they are
// (membrane_forces.hpp, MembraneSpec): one definition, which the engine's
// MembraneSpec and the job spec's specimen.membrane object
// (api/job_spec.hpp, MembraneSpec) both are, so that nothing copies them
// field by field. The defaults are the job spec's (the model spec §2–§3);
// the ranges are the job spec's (api/job_spec.cpp).
#pragma once

#include "state/membrane_edge_law.hpp"

namespace wiredem::engine {

struct MembraneMaterial {
    double thickness_m = 1e-3;          ///< d, the sheet's thickness [m]
    double mesh_size_m = 1.25e-3;       ///< l_m, the target edge length of the triangular mesh [m]
    double youngs_modulus_pa = 1e8;     ///< E_m [Pa]
    double poisson_ratio = 0.0;         ///< ν_m (for contacts only; see docs/model.md)
    double density_kg_per_m3 = 1000.0;  ///< ρ_m [kg/m³]
    /// How an edge acts when shorter than its rest length: tension_only,
    /// the sheet wrinkles (slack in compression), or linear.
    MembraneEdgeLaw edges = MembraneEdgeLaw::tension_only;
    friend bool operator==(const MembraneMaterial&, const MembraneMaterial&) = default;
};

} // namespace wiredem::engine
