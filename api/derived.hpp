// Quantities derived from a job spec that validation and the runner both
// need: the stable time step, the estimated body counts and the normal
// damping time. The inputs must be a spec whose fields are each in range
// (what parse_job_spec checks before it uses these); the cross-field checks
// need not hold. Pure and thread-safe.
#pragma once

#include "api/job_spec.hpp"
#include "timestep.hpp"

#include <cstdint>
#include <string>

namespace wiredem::api {

/// The stable time step of a job (the model spec §4): engine::stable_time_step.
using StableStep = engine::StableStep;

/// The stability inputs of a job's system before any World exists: one body
/// of each kind present in the job (the smallest grain, a wire node unless
/// the pattern is none, a membrane node) and the plates, all masses
/// multiplied by density_scale (wire nodes also by wire_mass_scale); the
/// wire's segments, k_elo = E_w π r_w² / l_w on m_w = ρ_w π r_w² l_w, and the
/// deformable membrane's edges, k_m = (√3/2) E_m d on m_m = (√3/2) l_m² ρ_m d.
[[nodiscard]] engine::StabilityInputs stability_inputs(const JobSpec& spec);

/// engine::stable_time_step of stability_inputs(spec).
[[nodiscard]] StableStep stable_time_step(const JobSpec& spec);

/// Estimated numbers of bodies of a job (used against engine.max_bodies).
struct BodyCounts {
    std::uint64_t grains = 0;          ///< specimen.grain_count
    std::uint64_t wire_nodes = 0;      ///< laid length ω R_a · H_m / v_z over l_w; 0 without wire
    std::uint64_t membrane_nodes = 0;  ///< (2πR / l_m) · (H_m / l_m · 2/√3), rounded up per factor
    /// All bodies together.
    [[nodiscard]] std::uint64_t total() const { return grains + wire_nodes + membrane_nodes; }
};

/// Estimates the body counts from the geometry (the preparation decides the
/// exact wire length).
[[nodiscard]] BodyCounts estimated_body_counts(const JobSpec& spec);

/// γ_n [s] the engine uses: the given one, or the one that gives the
/// requested restitution for a head-on collision of two grains of the mean
/// radius (masses scaled by density_scale) at the reference speed
/// (engine::hertz_damping_for_restitution_s).
[[nodiscard]] double resolved_normal_damping_s(const JobSpec& spec);

} // namespace wiredem::api
