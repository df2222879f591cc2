// Autocorrelation by direct sums; see autocorrelation.hpp.
#include "analysis/autocorrelation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace wiredem::engine::analysis {

std::optional<std::size_t> first_local_maximum_lag(std::span<const double> r) noexcept
{
    // k + 1 < size: the last value has no right neighbour and is never a maximum.
    for (std::size_t k = 1; k + 1 < r.size(); ++k)
        if (r[k - 1] < r[k] && r[k] >= r[k + 1]) return k;
    return std::nullopt;
}

Result<Autocorrelation, std::string> autocorrelation(
    std::span<const double> signal, double segment_length_m, std::size_t max_lag)
{
    const std::size_t n = signal.size();
    if (n < 2) return Err{"autocorrelation: signal has " + std::to_string(n) + " samples; need at least 2"};
    if (!std::isfinite(segment_length_m) || !(segment_length_m > 0.0)) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.6g", segment_length_m);
        return Err{std::string("autocorrelation: segment_length_m = ") + buf + " must be finite and > 0"};
    }
    double largest_abs = 0.0;
    for (std::size_t t = 0; t < n; ++t) {
        if (!std::isfinite(signal[t])) return Err{"autocorrelation: sample " + std::to_string(t) + " is not finite"};
        largest_abs = std::max(largest_abs, std::abs(signal[t]));
    }

    Autocorrelation out;
    for (double x : signal) out.mean += x;
    out.mean /= static_cast<double>(n);
    for (double x : signal) out.variance += (x - out.mean) * (x - out.mean);
    out.variance /= static_cast<double>(n);

    // A constant signal leaves rounding noise in μ, hence a tiny σ² that would make
    // R̂ pure noise: treat σ below 1e-12 of the signal's magnitude as zero.
    if (!(std::sqrt(out.variance) > 1e-12 * largest_abs) || out.variance == 0.0)
        return Err{std::string("autocorrelation: signal is constant (zero variance); no correlation defined")};

    const std::size_t last_lag = std::min(max_lag, n - 1);
    out.coefficients.resize(last_lag + 1);
    for (std::size_t k = 0; k <= last_lag; ++k) {
        double sum = 0.0;
        for (std::size_t t = 0; t + k < n; ++t) sum += (signal[t] - out.mean) * (signal[t + k] - out.mean);
        out.coefficients[k] = sum / (static_cast<double>(n - k) * out.variance);
    }

    out.first_maximum_lag = first_local_maximum_lag(out.coefficients);
    if (out.first_maximum_lag) out.first_maximum_lag_m = static_cast<double>(*out.first_maximum_lag) * segment_length_m;
    return out;
}

} // namespace wiredem::engine::analysis
