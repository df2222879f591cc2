// Quantities derived from a job spec that validation and the runner both
// need: the stable time step, the estimated body counts and the normal
// damping time. The inputs must be a spec whose fields are each in range
// (what parse_job_spec checks before it uses these); the cross-field checks
// need not hold. Pure and thread-safe.
#pragma once

#include "api/job_spec.hpp"
#include "timestep.hpp"

#include <cstdint>
#include <limits>
#include <numeric>
#include <span>
#include <string>
#include <vector>

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
    /// All bodies together, saturating like the counts: a hostile spec's
    /// count is the largest std::uint64_t, and a plain sum would wrap round
    /// to a small total that passes every limit (mesh_size_m = 1e-227).
    [[nodiscard]] std::uint64_t total() const
    {
        constexpr std::uint64_t most = std::numeric_limits<std::uint64_t>::max();
        std::uint64_t sum = grains;
        for (const std::uint64_t n : {wire_nodes, membrane_nodes}) sum = n > most - sum ? most : sum + n;
        return sum;
    }
};

/// Estimates the body counts from the geometry (the preparation decides the
/// exact wire length).
[[nodiscard]] BodyCounts estimated_body_counts(const JobSpec& spec);

/// The work a job asks for, estimated before it runs (the server refuses a
/// job above its limits, docs/api.md). Counts are doubles: a hostile spec can
/// ask for more steps than any integer holds (δt = 5e-324 s).
struct WorkEstimate {
    double time_step_s = 0.0;        ///< engine.time_step_s, or the auto step of the tests
    /// At most max_preparation_time_s of simulated time, at that step (the
    /// preparation's own auto step, set by impacts, is of the same order).
    double preparation_steps = 0.0;
    /// Each test's ramp, longest hold and loading to the target strain (at its
    /// plate speed) of a column as tall as the grains' estimated fill, in the
    /// order of triaxial.confining_pressures_pa.
    std::vector<double> test_steps;
    double samples_per_test = 0.0;   ///< rows of the time series of the longest test
    /// The free-standing test's longest run (removal, the longest settling,
    /// the dead load, the compression to the target); 0 when it does not run.
    double free_standing_steps = 0.0;
    /// Every test.
    [[nodiscard]] double tests_total_steps() const
    {
        return std::accumulate(test_steps.begin(), test_steps.end(), 0.0) + free_standing_steps;
    }
    /// Preparation and every test.
    [[nodiscard]] double total_steps() const { return preparation_steps + tests_total_steps(); }
};

/// Estimates the work of a job (inputs as for the functions above).
[[nodiscard]] WorkEstimate estimated_work(const JobSpec& spec);

/// How a campaign's overall progress (0–1) is shared among its stages, the
/// same whether its stages run in one process (campaign::run) or as jobs of
/// a cluster (the server's Slurm executor): preparation and tests share
/// 0–tests_end in proportion to their estimated steps; analysis and writing
/// the rest. The free-standing test (after the triaxial tests) is one more
/// test of its estimated steps.
struct ProgressShares {
    static constexpr double tests_end = 0.95;
    double preparation = 0.0;        ///< the preparation's share
    std::vector<double> tests;       ///< each test's share
    double free_standing = 0.0;      ///< the free-standing test's share (0 when the job has none)
    /// Overall progress from the preparation's fraction, each test's (in
    /// test order; tests beyond the span count as not begun), the analysis's
    /// and the free-standing test's. Divided by the same sum with every part
    /// done, so that a finished campaign is at exactly 1 (the shares' sum may
    /// round off it).
    [[nodiscard]] double overall(double preparation_fraction, std::span<const double> test_fractions,
        double analysis_fraction, double free_standing_fraction) const
    {
        double p = preparation * preparation_fraction + (1.0 - tests_end) * analysis_fraction
                 + free_standing * free_standing_fraction;
        double whole = preparation + (1.0 - tests_end) + free_standing;
        for (std::size_t k = 0; k < tests.size(); ++k) {
            p += tests[k] * (k < test_fractions.size() ? test_fractions[k] : 0.0);
            whole += tests[k];
        }
        return p / whole;
    }
};

/// The shares of a job, from its work estimate.
[[nodiscard]] ProgressShares progress_shares(const WorkEstimate& work);

/// The most time steps any job may take, preparation and tests together
/// (10¹⁵: three centuries at 10⁵ steps/s). Validation refuses a spec above
/// it, so `wiredem run` never meets a step count that no integer holds
/// (δt = 1e-83 s); servers limit jobs further (--max-steps-per-job, at most this).
inline constexpr double max_steps_of_any_job = 1e15;

/// The field a job's work is reported at when it is too much: the time step
/// when one is given, else what drives the larger part of the work, the
/// preparation's time limit or the plate speed.
[[nodiscard]] std::string work_field(const JobSpec& spec, const WorkEstimate& work);

/// γ_n [s] the engine uses: the given one, or the one that gives the
/// requested restitution for a head-on collision of two grains of the mean
/// radius (masses scaled by density_scale) at the reference speed
/// (engine::hertz_damping_for_restitution_s).
[[nodiscard]] double resolved_normal_damping_s(const JobSpec& spec);

} // namespace wiredem::api
