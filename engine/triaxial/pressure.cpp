// The confining pressure's ramp; see pressure.hpp.
#include "triaxial/pressure.hpp"

#include <cmath>
#include <numbers>

namespace wiredem::engine {

double ramped_pressure_pa(double target_pa, double t_s, double ramp_s) noexcept
{
    if (t_s >= ramp_s) return target_pa;
    return target_pa * 0.5 * (1.0 - std::cos(std::numbers::pi * t_s / ramp_s));
}

} // namespace wiredem::engine
