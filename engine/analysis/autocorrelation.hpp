// Autocorrelation of the segment strain along the wire (the model spec §7).
//
//   R̂(k) = 1/((N − k) σ²) Σ_{t=1}^{N−k} (X_t − μ)(X_{t+k} − μ),   k = 0 … K
//
// with μ and σ² the mean and the population variance (1/N) of the whole signal, so
// R̂(0) = 1. The characteristic length of the wire's strain pattern is the lag of the
// first local maximum after k = 0, reported as an index and in metres (k · l_w).
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

/// The autocorrelation of one signal and its first maximum.
struct Autocorrelation {
    std::vector<double> coefficients; ///< R̂(k) for k = 0 … max lag; R̂(0) = 1
    double mean = 0.0;                ///< μ, in the signal's unit
    double variance = 0.0;            ///< σ² (population, 1/N), in the signal's unit squared

    /// Lag k of the first local maximum after k = 0: the first k > 0 with
    /// R̂(k−1) < R̂(k) ≥ R̂(k+1). The last computed lag never qualifies (it has no
    /// right neighbour). Empty when R̂ has no such maximum (e.g. it decays monotonically).
    std::optional<std::size_t> first_maximum_lag;
    /// The same lag in metres, k · segment length [m]; empty exactly when the index is.
    std::optional<double> first_maximum_lag_m;
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

} // namespace wiredem::engine::analysis
