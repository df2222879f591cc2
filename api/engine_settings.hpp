// The engine's inputs from a job spec: the preparation spec and the settings
// of each triaxial test. Kept here, next to the parser and the derived
// quantities that validation uses (stable time step, damping time), so that
// what the server validates and what the runner (`wiredem run`) executes
// cannot drift apart. The input must be a valid spec (parse_job_spec). Pure
// and thread-safe.
#pragma once

#include "api/job_spec.hpp"
#include "specimen/box_preparation.hpp"
#include "specimen/preparation.hpp"
#include "specimen/wire_cuts.hpp"
#include "triaxial/free_standing.hpp"
#include "triaxial/triaxial.hpp"

namespace wiredem::api {

/// The preparation of the job's specimen (the model spec §5): geometry,
/// materials, wire and pattern, membrane, contact law (γ_n resolved from the
/// restitution if given so), density scaling, pouring end, δt (0 = auto), seed.
[[nodiscard]] engine::PreparationSpec preparation_spec(const JobSpec& spec);

/// preparation_spec with the normal damping left at 0, not resolved: all
/// that the estimates of a job's fill height, wire length and work read
/// (engine::estimated_fill_height_m, estimated_wire_length_m), which
/// validation computes several times per spec, without the collision fit a
/// restitution costs (tens to hundreds of ms: resolved_normal_damping_s).
[[nodiscard]] engine::PreparationSpec preparation_geometry(const JobSpec& spec);

/// The nozzle's pattern of a job's wire: kind, the built-in patterns'
/// parameters, the toolpath's points.
[[nodiscard]] engine::PatternSpec pattern_spec(const WireSpec& w);

/// Where the job cuts the prepared wire (specimen.wire.cuts_at_m, cut_every_loops).
[[nodiscard]] engine::WireCuts wire_cuts(const JobSpec& spec);

/// The settings of the job's test `test` (an index into
/// triaxial.confining_pressures_pa) (the model spec §6).
[[nodiscard]] engine::TriaxialSettings triaxial_settings(const JobSpec& spec, std::size_t test);

/// The box preparation of a cuboid-cell job (triaxial.cell = cuboid): the
/// poured specimen's grains (engine::box_preparation_from), compacted to the
/// lowest confining pressure, with triaxial.cuboid's aspect ratio, wall and
/// compaction friction. An error for what the box cannot hold (clumps).
[[nodiscard]] engine::Result<engine::BoxPreparationSpec, std::string> box_preparation_spec(const JobSpec& spec);

/// box_preparation_spec with the normal damping left at 0, not resolved (as
/// preparation_geometry): what validation asks engine::box_preparation_error
/// about, without the collision fit (1.4 s of CPU in the fuzz build for a
/// grain modulus of 5e-324: fuzz_job_spec_values, 2026-12-06).
[[nodiscard]] engine::Result<engine::BoxPreparationSpec, std::string> box_preparation_geometry(const JobSpec& spec);

/// The settings of the job's free-standing test (free_standing; whether it
/// runs is free_standing.enabled).
[[nodiscard]] engine::FreeStandingSettings free_standing_settings(const JobSpec& spec);
/// The engine's sieve curve for a job's grain sizes.
[[nodiscard]] engine::SieveCurve sieve_curve(const GrainSizesSpec& g);
/// The clump a job's grain shape describes, at a volume-equivalent radius of
/// 1 m (engine::unit_clump_shape; its mass properties computed here, ~50 ms,
/// once per shape: later calls return the kept body).
[[nodiscard]] engine::ClumpBody grain_shape_body(const GrainShapeSpec& g);

/// The grain that stands for all where one size is needed (the restitution
/// fit's head-on pair): r_p, or half the curve's D50 (by mass) [m].
[[nodiscard]] double reference_grain_radius_m(const SpecimenSpec& s);

} // namespace wiredem::api
