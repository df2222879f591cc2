// The formwork of a column test; see formwork.hpp.
#include "triaxial/formwork.hpp"

#include "forces/membrane_forces.hpp"

#include <cmath>

namespace wiredem::engine {

std::vector<std::uint32_t> seal_membrane_to_cap(World& w, std::size_t top_plate_wall)
{
    std::vector<std::uint32_t> cap_nodes;
    set_membrane_rigid(w, false);
    const TranslationalState& nodes = w.of(BodyKind::membrane);
    const double plate_z = w.walls[top_plate_wall].point_m.z();
    for (std::uint32_t i = 0; i < nodes.size(); ++i) {
        if (nodes.x[0][i].z() + nodes.radius_m[i] <= plate_z) continue;
        set_motion(w, {BodyKind::membrane, i}, Motion::kinematic); // moves with the plate (carry_with_cap)
        set_velocity(w, {BodyKind::membrane, i}, Vec3::Zero());
        cap_nodes.push_back(i);
    }
    return cap_nodes;
}

void carry_with_cap(World& w, const std::vector<std::uint32_t>& cap_nodes, std::size_t top_plate_wall)
{
    const Vec3 v = w.walls[top_plate_wall].velocity_m_per_s;
    for (std::uint32_t i : cap_nodes) set_velocity(w, {BodyKind::membrane, i}, v);
}

void open_formwork(World& w, double speed_m_per_s)
{
    const TranslationalState& nodes = w.of(BodyKind::membrane);
    for (std::uint32_t i = 0; i < nodes.size(); ++i) {
        const Vec3& x = nodes.x[0][i];
        const double rho = std::hypot(x.x(), x.y());
        const Vec3 v = rho > 0.0 ? Vec3(Vec3(x.x() / rho, x.y() / rho, 0.0) * speed_m_per_s) : Vec3(Vec3::Zero());
        set_motion(w, {BodyKind::membrane, i}, Motion::kinematic);
        set_velocity(w, {BodyKind::membrane, i}, v);
    }
}

void close_formwork(World& w)
{
    const TranslationalState& nodes = w.of(BodyKind::membrane);
    for (std::uint32_t i = 0; i < nodes.size(); ++i) set_motion(w, {BodyKind::membrane, i}, Motion::fixed);
    set_kinds_interact(w, BodyKind::grain, BodyKind::membrane, false);
    set_kinds_interact(w, BodyKind::wire, BodyKind::membrane, false);
}

} // namespace wiredem::engine
