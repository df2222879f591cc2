// The loading phase of a column test; see loading.hpp.
#include "triaxial/loading.hpp"

namespace wiredem::engine {

double loading_time_s(double target_axial_strain, double height_m, double plate_speed_m_per_s) noexcept
{
    return target_axial_strain * height_m / plate_speed_m_per_s;
}

} // namespace wiredem::engine
