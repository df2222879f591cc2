// Consolidation of a triaxial test; see consolidation.hpp.
#include "triaxial/consolidation.hpp"

#include "analysis/stress.hpp"

#include <algorithm>
#include <cmath>

namespace wiredem::engine {

double consolidation_window_mean(const TriaxialSeries& s, const std::vector<double>& column, std::size_t last)
{
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = last + 1; i-- > 0 && s.time_s[i] >= s.time_s[last] - consolidation_window_s; ++n)
        sum += column[i];
    return sum / static_cast<double>(n);
}

std::optional<LoadingStart> loading_start(const TriaxialSeries& s)
{
    const auto loading = static_cast<std::uint8_t>(TriaxialPhase::loading);
    const auto row = std::find(s.phase.begin(), s.phase.end(), loading);
    if (row == s.phase.end()) return std::nullopt;
    LoadingStart l;
    l.sample = static_cast<std::size_t>(row - s.phase.begin());
    l.sigma1_pa = consolidation_window_mean(s, s.sigma1_pa, l.sample);
    l.sigma3_effective_pa = consolidation_window_mean(s, s.sigma3_effective_pa, l.sample);
    l.stress_ratio = analysis::stress_ratio(l.sigma1_pa, l.sigma3_effective_pa);
    const double h_first = s.height_m.front();
    const double h_min = *std::min_element(s.height_m.begin(), s.height_m.begin() + static_cast<std::ptrdiff_t>(l.sample) + 1);
    l.axial_strain = analysis::axial_strain(h_first, s.height_m[l.sample]);
    l.rebound_axial_strain = (s.height_m[l.sample] - h_min) / h_first;
    l.radial_strain = (s.column_radius_m.front() - s.column_radius_m[l.sample]) / s.column_radius_m.front();
    return l;
}

bool within_consolidation_mismatch(double sigma1_pa, double target_pa) noexcept
{
    return std::isfinite(sigma1_pa) && std::isfinite(target_pa)
        && std::abs(sigma1_pa - target_pa) <= max_consolidation_mismatch * std::abs(target_pa);
}

std::optional<Consolidation> consolidation_from_string(std::string_view text) noexcept
{
    return value_named(consolidation_names, text);
}

double piston_velocity_m_per_s(double velocity_m_per_s, double target_force_n, double plate_force_n,
    double dt_s, double piston_mass_kg, double max_speed_m_per_s) noexcept
{
    const double net_down_n = target_force_n - plate_force_n;
    return std::clamp(velocity_m_per_s - dt_s * net_down_n / piston_mass_kg, -max_speed_m_per_s, max_speed_m_per_s);
}

} // namespace wiredem::engine
