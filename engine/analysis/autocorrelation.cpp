// Autocorrelation by direct sums, and its maxima; see autocorrelation.hpp.
#include "analysis/autocorrelation.hpp"

#include "core/format.hpp"

#include <algorithm>
#include <cmath>

namespace wiredem::engine::analysis {

std::optional<std::size_t> first_local_maximum_lag(std::span<const double> r) noexcept
{
    // k + 1 < size: the last value has no right neighbour and is never a maximum.
    for (std::size_t k = 1; k + 1 < r.size(); ++k)
        if (r[k - 1] < r[k] && r[k] >= r[k + 1]) return k;
    return std::nullopt;
}

double white_noise_band_95(std::size_t samples, std::size_t lag) noexcept
{
    return 1.96 / std::sqrt(static_cast<double>(samples - lag));
}

double peak_prominence(std::span<const double> r, std::size_t first, std::size_t last) noexcept
{
    const double top = r[first];
    // Each side's lowest value before R̂ rises above the top; the top itself when
    // the first step already rises (then the prominence is 0).
    double left_low = top;
    for (std::size_t j = first; j-- > 0 && !(r[j] > top);) left_low = std::min(left_low, r[j]);
    double right_low = top;
    for (std::size_t j = last + 1; j < r.size() && !(r[j] > top); ++j) right_low = std::min(right_low, r[j]);
    return top - std::max(left_low, right_low);
}

std::optional<std::size_t> first_prominent_maximum_lag(std::span<const double> r, std::span<const double> band) noexcept
{
    const std::size_t lags = std::min(r.size(), band.size());
    std::size_t k = 1;
    while (k < lags) {
        if (!(r[k - 1] < r[k])) {
            ++k;
            continue;
        }
        std::size_t last = k; // the top: a run of equal values, reported at its first index
        while (last + 1 < r.size() && r[last + 1] == r[k]) ++last;
        if (last + 1 < r.size() && r[last + 1] < r[k] && peak_prominence(r, k, last) > band[k]) return k;
        k = last + 1;
    }
    return std::nullopt;
}

Result<Autocorrelation, std::string> autocorrelation(
    std::span<const double> signal, double segment_length_m, std::size_t max_lag)
{
    const std::size_t n = signal.size();
    if (n < 2) return Err{"autocorrelation: signal has " + std::to_string(n) + " samples; need at least 2"};
    if (!std::isfinite(segment_length_m) || !(segment_length_m > 0.0))
        return Err{"autocorrelation: segment_length_m = " + format_number(segment_length_m, 6) + " must be finite and > 0"};
    double largest_abs = 0.0;
    for (std::size_t t = 0; t < n; ++t) {
        if (!std::isfinite(signal[t])) return Err{"autocorrelation: sample " + std::to_string(t) + " is not finite"};
        largest_abs = std::max(largest_abs, std::abs(signal[t]));
    }

    Autocorrelation out;
    out.samples = n;
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

    const auto in_metres = [&](std::optional<std::size_t> k) {
        return k ? std::optional<double>(static_cast<double>(*k) * segment_length_m) : std::nullopt;
    };
    out.first_maximum_lag = first_local_maximum_lag(out.coefficients);
    out.first_maximum_lag_m = in_metres(out.first_maximum_lag);
    std::vector<double> band(out.coefficients.size());
    for (std::size_t k = 0; k < band.size(); ++k) band[k] = white_noise_band_95(n, k);
    out.prominent_maximum_lag = first_prominent_maximum_lag(out.coefficients, band);
    out.prominent_maximum_lag_m = in_metres(out.prominent_maximum_lag);
    return out;
}

} // namespace wiredem::engine::analysis
