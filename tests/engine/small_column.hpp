// The small column of the preparation tests (test_preparation.cpp) and of the
// settling test (test_settling.cpp).
#pragma once

#include "laws/hertz.hpp"
#include "specimen/preparation.hpp"

#include <cmath>
#include <cstddef>
#include <numbers>

namespace wiredem::engine::test {

/// R = 8 mm, R_a = 4 mm, R_i = 1.5 mm; masses × 100 and wire nodes × 400
/// more (quasi-static scaling) so that a preparation takes ~10⁴ steps; poured
/// at 0.3 m/s; e_n = 0.3 at 0.1 m/s.
inline PreparationSpec small_column(PatternKind kind, std::size_t grains)
{
    PreparationSpec s;
    s.membrane_radius_m = 8e-3;
    s.membrane_height_m = 0.04;
    s.grain_count = grains;
    s.pattern.pattern = kind;
    s.pattern.helix_radius_m = 4e-3;
    s.pattern.inner_radius_m = 1.5e-3;
    s.density_scale = 100.0;
    s.wire_mass_scale = 400.0;
    s.fill_rate_m_per_s = 0.3;
    s.max_time_s = 1.5;
    const double grain_mass = s.density_scale * s.grain.density_kg_per_m3 * 4.0 / 3.0 * std::numbers::pi
                            * std::pow(s.grain_radius_m, 3);
    const double e_star = effective_modulus_pa(s.grain.youngs_modulus_pa, s.grain.poisson_ratio,
        s.grain.youngs_modulus_pa, s.grain.poisson_ratio);
    s.contact.normal_damping_s = hertz_damping_for_restitution_s(0.3, 0.5 * grain_mass, 0.1, e_star, 0.5 * s.grain_radius_m);
    return s;
}

} // namespace wiredem::engine::test
