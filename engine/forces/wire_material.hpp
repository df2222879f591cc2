// The wire's material that a job gives as it is (wire_forces.hpp, WireSpec):
// one definition, which the engine's WireSpec and the job spec's
// specimen.wire object (api/job_spec.hpp, WireSpec) both are, so that
// nothing copies it field by field. The defaults are the job spec's (the
// paper's wire, the model spec §2); the ranges are the job spec's
// (api/job_spec.cpp).
#pragma once

namespace wiredem::engine {

struct WireMaterial {
    double radius_m = 5e-4;             ///< r_w, the contact radius of a node [m]
    double segment_length_m = 1.25e-3;  ///< l_w, the rest length of a segment [m]
    double youngs_modulus_pa = 1e9;     ///< E_w [Pa]
    double poisson_ratio = 0.0;         ///< ν_w
    double density_kg_per_m3 = 1000.0;  ///< ρ_w [kg/m³]
    friend bool operator==(const WireMaterial&, const WireMaterial&) = default;
};

/// ε_y = σ_y/E_w, the wire's yield strain in bending by default: a
/// polyamide-like wire (σ_y = 50 MPa at E_w = 1 GPa; docs/model.md, "Wire").
/// The default of both the engine's WireSpec and the job's
/// specimen.wire.bending_yield_strain (where "elastic" is +∞ here).
inline constexpr double default_bending_yield_strain = 0.05;

} // namespace wiredem::engine
