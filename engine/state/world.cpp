#include "state/world.hpp"

#include <cmath>
#include <numbers>

namespace wiredem::engine {

std::uint8_t add_material(World& w, const Material& m)
{
    return w.materials.add(m);
}

std::uint32_t add_grain(World& w, const Vec3& position_m, double radius_m, std::uint8_t material,
    const Vec3& velocity_m_per_s, const Vec3& angular_velocity_rad_per_s)
{
    const double mass = sphere_mass_kg(w.materials[material].density_kg_per_m3, radius_m);
    const std::uint32_t id = w.of(BodyKind::grain).add(position_m, velocity_m_per_s, radius_m, mass, material, w.dt_s);
    w.grain_rotation.add(0.4 * mass * radius_m * radius_m); // solid sphere: I = 2/5 m r²
    w.grain_rotation.theta[1].back() = angular_velocity_rad_per_s * w.dt_s;
    w.force_of(BodyKind::grain).push_back(Vec3::Zero());
    w.grain_torque_n_m.push_back(Vec3::Zero());
    w.neighbours_dirty = true;
    invalidate_prediction(w);
    return id;
}

std::uint32_t add_node(World& w, BodyKind kind, const Vec3& position_m, double radius_m, double mass_kg,
    std::uint8_t material, const Vec3& velocity_m_per_s)
{
    const std::uint32_t id = w.of(kind).add(position_m, velocity_m_per_s, radius_m, mass_kg, material, w.dt_s);
    w.force_of(kind).push_back(Vec3::Zero());
    w.neighbours_dirty = true;
    invalidate_prediction(w);
    return id;
}

std::size_t add_wall(World& w, Wall wall)
{
    w.walls.push_back(std::move(wall));
    w.wall_point_at_build_m.push_back(w.walls.back().point_m);
    w.wall_loads.emplace_back();
    w.contacts.append_wall();
    w.neighbours_dirty = true;
    return w.walls.size() - 1;
}

void remove_wall(World& w, std::size_t wall)
{
    const auto at = static_cast<std::ptrdiff_t>(wall);
    w.walls.erase(w.walls.begin() + at);
    w.wall_point_at_build_m.erase(w.wall_point_at_build_m.begin() + at);
    w.wall_loads.erase(w.wall_loads.begin() + at);
    w.contacts.remove_wall(wall, w.flat_offsets());
    w.neighbours_dirty = true;
}

Wall make_plate(double z_m, double normal_sign, std::uint8_t material)
{
    Wall wall;
    wall.shape = Wall::Shape::plane;
    wall.point_m = Vec3(0.0, 0.0, z_m);
    wall.normal = Vec3(0.0, 0.0, normal_sign >= 0.0 ? 1.0 : -1.0);
    wall.material = material;
    return wall;
}

Wall make_cylinder(double radius_m, std::uint8_t material)
{
    Wall wall;
    wall.shape = Wall::Shape::cylinder;
    wall.radius_m = radius_m;
    wall.material = material;
    return wall;
}

void set_time_step(World& w, double dt_s)
{
    invalidate_prediction(w);
    State& s = w;
    const double ratio = dt_s / s.dt_s;
    double scale = 1.0;
    for (int k = 1; k < gear_order; ++k) {
        scale *= ratio;
        for (auto& body : s.bodies)
            for (Vec3& v : body.x[k]) v *= scale;
        for (Vec3& v : s.grain_rotation.theta[k]) v *= scale;
    }
    s.dt_s = dt_s;
}

void set_integrator(World& w, Integrator integrator)
{
    if (integrator == w.integrator) return;
    invalidate_prediction(w);
    for (int k = 3; k < gear_order; ++k) {
        for (auto& body : w.bodies)
            for (Vec3& v : body.x[k]) v.setZero();
        for (Vec3& v : w.grain_rotation.theta[k]) v.setZero();
    }
    w.integrator = integrator;
}

Vec3 velocity_m_per_s(const State& s, BodyRef b)
{
    return s.of(b.kind()).x[1][b.index()] / s.dt_s;
}

Vec3 angular_velocity_rad_per_s(const State& s, std::uint32_t grain)
{
    return s.grain_rotation.theta[1][grain] / s.dt_s;
}

void set_velocity(World& w, BodyRef b, const Vec3& v_m_per_s)
{
    invalidate_prediction(w);
    w.of(b.kind()).x[1][b.index()] = v_m_per_s * w.dt_s;
}

void set_motion(World& w, BodyRef b, Motion motion)
{
    TranslationalState& body = w.of(b.kind());
    const std::uint32_t i = b.index();
    if (body.motion[i] == motion) return;
    invalidate_prediction(w);
    body.motion[i] = motion;
    const int first_zeroed = motion == Motion::fixed ? 1 : motion == Motion::kinematic ? 2 : gear_order;
    for (int k = first_zeroed; k < gear_order; ++k) body.x[k][i].setZero();
    if (b.kind() == BodyKind::grain && motion != Motion::dynamic) // it does not turn
        for (int k = 1; k < gear_order; ++k) w.grain_rotation.theta[k][i].setZero();
    w.neighbours_dirty = true;
}

void set_kinds_interact(World& w, BodyKind a, BodyKind b, bool interact)
{
    const auto i = static_cast<std::size_t>(a), j = static_cast<std::size_t>(b);
    w.kinds_interact[i][j] = w.kinds_interact[j][i] = interact;
    w.neighbours_dirty = true;
}

void place_body(World& w, BodyRef b, const Vec3& position_m)
{
    TranslationalState& body = w.of(b.kind());
    const std::uint32_t i = b.index();
    invalidate_prediction(w);
    body.x[0][i] = position_m;
    for (int k = 1; k < gear_order; ++k) body.x[k][i].setZero();
    if (b.kind() == BodyKind::grain)
        for (int k = 1; k < gear_order; ++k) w.grain_rotation.theta[k][i].setZero();
    w.neighbours_dirty = true;
}

void scale_velocities(World& w, double factor)
{
    invalidate_prediction(w);
    for (auto& body : w.bodies)
        for (Vec3& v : body.x[1]) v *= factor;
    for (Vec3& v : w.grain_rotation.theta[1]) v *= factor;
}

void invalidate_neighbours(World& w)
{
    w.neighbours_dirty = true;
}

} // namespace wiredem::engine
