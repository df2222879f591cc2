// Autocorrelation of the segment strain along the wire (the model spec §7).
//
//   R̂(k) = 1/((N − k) σ²) Σ_{t=1}^{N−k} (X_t − μ)(X_{t+k} − μ),   k = 0 … K
//
// with μ and σ² the mean and the population variance (1/N) of the whole signal, so
// R̂(0) = 1. The characteristic length of the wire's strain pattern is read from
// the maxima of R̂ after k = 0, reported as an index and in metres (k · l_w), twice:
//
// * the first local maximum, the spec's literal definition;
// * the first *prominent* maximum: the first local maximum that stands out of the
//   estimator's own noise. R̂ of a real wire decays from 1 with bumps of 10⁻⁴ on
//   its shoulder (the study's helix column at 80 kPa, 7991 segments: a bump of
//   0.0004 at k = 32, 40 mm, before the dip at 77.5 mm and the real hump at
//   117.5 mm), and the literal reading takes such a bump for the pattern's length.
//   A maximum counts when its topographic prominence — its height above the higher
//   of the lowest points reached on each side before R̂ rises above it again (or
//   the computed lags end) — exceeds Bartlett's 95 % band of R̂ for white noise,
//   1.96/√(N − k) at its lag (≈ 0.022 at k ≈ 100 of 7991 samples). For a
//   correlated signal the band is wider — Bartlett's variance of R̂(k) is
//   (1 + 2 Σ_{j=1}^{k−1} R(j)²)/N for a signal correlated over fewer than k lags,
//   not white noise's 1/N — so this band is a lower bound: the criterion rejects
//   only bumps that white noise alone would make, and a maximum it accepts can
//   still be noise of a correlated signal.
//
// Direct O(N·K) sums, evaluated in a fixed order (deterministic); N ≈ 10⁴ segments
// costs well under a second. Pure functions, thread safe.
#pragma once

#include "core/result.hpp"

#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace wiredem::engine::analysis {

/// Largest lag "as many as the signal allows" (N − 1).
inline constexpr std::size_t all_lags = std::numeric_limits<std::size_t>::max();

/// The autocorrelation of one signal and its first (prominent) maximum.
struct Autocorrelation {
    std::vector<double> coefficients; ///< R̂(k) for k = 0 … max lag; R̂(0) = 1
    double mean = 0.0;                ///< μ, in the signal's unit
    double variance = 0.0;            ///< σ² (population, 1/N), in the signal's unit squared
    std::size_t samples = 0;          ///< N, the signal's length

    /// Lag k of the first local maximum after k = 0: the first k > 0 with
    /// R̂(k−1) < R̂(k) ≥ R̂(k+1). The last computed lag never qualifies (it has no
    /// right neighbour). Empty when R̂ has no such maximum (e.g. it decays monotonically).
    std::optional<std::size_t> first_maximum_lag;
    /// The same lag in metres, k · segment length [m]; empty exactly when the index is.
    std::optional<double> first_maximum_lag_m;

    /// Lag of the first prominent maximum: first_prominent_maximum_lag of the
    /// coefficients with the band white_noise_band_95(samples, k). Never before
    /// first_maximum_lag; empty when no maximum stands out of the band.
    std::optional<std::size_t> prominent_maximum_lag;
    /// The same lag in metres [m]; empty exactly when the index is.
    std::optional<double> prominent_maximum_lag_m;
};

/// Autocorrelation of a signal sampled every `segment_length_m` metres (the wire's
/// segment strains, one per segment in chain order) for lags 0 … min(max_lag, N − 1).
/// Errors: fewer than 2 samples; a non-finite sample; segment_length_m not finite and
/// > 0; a constant signal (σ = 0, or σ below 1e-12 of the largest |X|: no correlation
/// is defined).
[[nodiscard]] Result<Autocorrelation, std::string> autocorrelation(
    std::span<const double> signal, double segment_length_m, std::size_t max_lag = all_lags);

/// Index of the first local maximum after k = 0 of a correlation sequence:
/// the first k in [1, size − 2] with r[k−1] < r[k] ≥ r[k+1]; empty if none.
[[nodiscard]] std::optional<std::size_t> first_local_maximum_lag(std::span<const double> r) noexcept;

/// Bartlett's 95 % band of R̂(k) for white noise of `samples` values: 1.96/√(N − k),
/// the half-width within which 95 % of white noise's R̂(k) fall (k < N).
[[nodiscard]] double white_noise_band_95(std::size_t samples, std::size_t lag) noexcept;

/// Topographic prominence of the maximum of r whose top is the run of equal values
/// r[first] … r[last]: r[first] minus the higher of the two lowest values met walking
/// away from the top on each side until a value above r[first] or the end of r.
/// Zero when the top is not above its neighbour on some side, or has none (a top at
/// either end of r). Requires first ≤ last < size.
[[nodiscard]] double peak_prominence(std::span<const double> r, std::size_t first, std::size_t last) noexcept;

/// Index of the first prominent maximum after k = 0 of a correlation sequence: the
/// first local maximum whose prominence exceeds band[k]. A maximum is a run of equal
/// values r[a] … r[b] with r[a−1] < r[a] and r[b] > r[b+1] (a ≥ 1; so the last value,
/// with no right neighbour, never is one), reported at its first index a; a run that
/// rises again afterwards (a step) is no maximum. Lags without a band value
/// (k ≥ band.size()) never qualify. Empty if no maximum qualifies.
[[nodiscard]] std::optional<std::size_t> first_prominent_maximum_lag(
    std::span<const double> r, std::span<const double> band) noexcept;

} // namespace wiredem::engine::analysis
