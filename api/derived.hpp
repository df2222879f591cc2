// Quantities derived from a job spec that validation and the runner both
// need: the stable time step, the estimated body counts and the normal
// damping time. The inputs must be a spec whose fields are each in range
// (what parse_job_spec checks before it uses these); the cross-field checks
// need not hold. Pure and thread-safe.
#pragma once

#include "api/job_spec.hpp"

#include <cstdint>
#include <string>

namespace wiredem::api {

/// The stable time step of a job (the model spec §4).
struct StableStep {
    double critical_s = 0.0;   ///< largest stable δt [s]
    double auto_s = 0.0;       ///< what `"time_step_s": "auto"` uses: engine::auto_time_step_fraction × critical_s [s]
    std::string limited_by;    ///< what sets critical_s, e.g. "wire segments", "grain–grain contacts"
};

/// Builds a probe engine::World with one body of each kind present in the
/// job (the smallest grain, a wire node unless the pattern is none, a
/// membrane node) and the bottom plate, all masses multiplied by
/// density_scale (wire nodes also by wire_mass_scale), and calls engine::critical_time_step; then folds in the
/// springs: wire segments ω² = 4 k_elo / m_w, k_elo = E_w π r_w² / l_w,
/// m_w = ρ_w π r_w² l_w, and membrane edges ω² = 12 k_m / m_m,
/// k_m = (√3/2) E_m d, m_m = (√3/2) l_m² ρ_m d.
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
