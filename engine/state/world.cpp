#include "state/world.hpp"

#include "core/assert.hpp"

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
    if (!w.clumps.member_clump.empty()) { // a free grain beside clumps
        w.clumps.member_clump.push_back(ClumpState::none);
        w.clumps.member_offset_m.push_back(Vec3::Zero());
    }
    w.neighbours_dirty = true;
    invalidate_prediction(w);
    return id;
}

std::uint32_t add_clump(World& w, const ClumpBody& body, const Vec3& position_m, const Quat& orientation,
    std::uint8_t material, const Vec3& velocity_m_per_s, const Vec3& angular_velocity_rad_per_s)
{
    WIREDEM_ASSERT(!body.spheres.empty(), "a clump has spheres");
    ClumpState& c = w.clumps;
    TranslationalState& grains = w.of(BodyKind::grain);
    if (c.member_clump.empty()) { // the first clump: the per-grain arrays appear
        c.member_clump.assign(grains.size(), ClumpState::none);
        c.member_offset_m.assign(grains.size(), Vec3::Zero());
    }
    const double density = w.materials[material].density_kg_per_m3;
    const auto id = static_cast<std::uint32_t>(c.size());
    const Quat q = orientation.normalized();
    c.x[0].push_back(position_m);
    c.x[1].push_back(velocity_m_per_s * w.dt_s);
    const Vec3 omega_body = q.conjugate() * angular_velocity_rad_per_s;
    c.omega[0].push_back(Vec3::Zero());
    c.omega[1].push_back(omega_body * w.dt_s);
    for (int k = 2; k < gear_order; ++k) {
        c.x[k].push_back(Vec3::Zero());
        c.omega[k].push_back(Vec3::Zero());
    }
    c.orientation.push_back(q);
    c.mass_kg.push_back(density * body.volume_m3);
    c.principal_inertia_kg_m2.push_back(density * body.principal_inertia_m5);
    c.first_member.push_back(static_cast<std::uint32_t>(grains.size()));
    c.member_count.push_back(static_cast<std::uint32_t>(body.spheres.size()));
    for (const ClumpSphere& s : body.spheres) {
        // No mass of its own: nothing integrates it, gravity acts on the clump.
        grains.add(position_m, Vec3::Zero(), s.radius_m, 0.0, material, w.dt_s);
        grains.motion.back() = Motion::clumped;
        w.grain_rotation.add(0.0);
        w.force_of(BodyKind::grain).push_back(Vec3::Zero());
        w.grain_torque_n_m.push_back(Vec3::Zero());
        c.member_clump.push_back(id);
        c.member_offset_m.push_back(s.centre_m);
    }
    w.clump_loads.force_n.push_back(Vec3::Zero());
    w.clump_loads.torque_n_m.push_back(Vec3::Zero());
    w.clump_loads.predicted_orientation.push_back(q);
    place_clump_spheres(w, id, q);
    w.neighbours_dirty = true;
    invalidate_prediction(w);
    return id;
}

namespace {

/// Sphere i of a clump at centre X, velocity δt V and spin δt ω, lever arm q b.
inline void put_clump_sphere(State& s, std::uint32_t i, const Vec3& centre, const Vec3& velocity, const Vec3& spin,
    const Vec3& arm)
{
    TranslationalState& grains = s.of(BodyKind::grain);
    grains.x[0][i] = centre + arm;
    grains.x[1][i] = velocity + spin.cross(arm); // δt (v + ω × r)
    s.grain_rotation.theta[1][i] = spin;
}

} // namespace

void place_clump_spheres(State& s, std::uint32_t clump, const Quat& q, Vec3* arm_m)
{
    const ClumpState& c = s.clumps;
    const Vec3 centre = c.x[0][clump], velocity = c.x[1][clump];
    const Vec3 spin = q * c.omega[1][clump]; // δt ω in space
    const std::uint32_t end = c.first_member[clump] + c.member_count[clump];
    for (std::uint32_t i = c.first_member[clump]; i < end; ++i) {
        const Vec3 arm = q * c.member_offset_m[i];
        if (arm_m != nullptr) arm_m[i] = arm;
        put_clump_sphere(s, i, centre, velocity, spin, arm);
    }
}

void place_clump_spheres_at_arms(State& s, std::uint32_t clump, const Quat& q, const Vec3* arm_m)
{
    const ClumpState& c = s.clumps;
    const Vec3 centre = c.x[0][clump], velocity = c.x[1][clump];
    const Vec3 spin = q * c.omega[1][clump];
    const std::uint32_t end = c.first_member[clump] + c.member_count[clump];
    for (std::uint32_t i = c.first_member[clump]; i < end; ++i) put_clump_sphere(s, i, centre, velocity, spin, arm_m[i]);
}

double clump_sphere_effective_mass_kg(const State& s, std::size_t grain)
{
    const ClumpState& c = s.clumps;
    const std::uint32_t i = c.member_clump[grain];
    const double smallest_inertia = c.principal_inertia_kg_m2[i].minCoeff();
    return 1.0 / (1.0 / c.mass_kg[i] + c.member_offset_m[grain].squaredNorm() / smallest_inertia);
}

Vec3 clump_angular_velocity_rad_per_s(const State& s, std::uint32_t clump)
{
    return s.clumps.orientation[clump] * s.clumps.omega[1][clump] / s.dt_s;
}

Vec3 clump_angular_momentum(const State& s, std::uint32_t clump)
{
    const ClumpState& c = s.clumps;
    const Vec3 l_body = c.principal_inertia_kg_m2[clump].cwiseProduct(c.omega[1][clump]) / s.dt_s;
    return c.orientation[clump] * l_body;
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
        for (Vec3& v : s.clumps.x[k]) v *= scale;
        for (Vec3& v : s.clumps.omega[k]) v *= scale;
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
        for (Vec3& v : w.clumps.x[k]) v.setZero();
        for (Vec3& v : w.clumps.omega[k]) v.setZero();
    }
    // A clump's omega[2] is δt²/2 ω̇_b under Gear-5 and δt²/2 I⁻¹τ_b under
    // Verlet; they differ by the gyroscopic term, ½ I⁻¹(w₁ × I w₁) with w₁ = δt ω_b.
    ClumpState& c = w.clumps;
    const double sign = integrator == Integrator::verlet ? 1.0 : -1.0;
    for (std::size_t i = 0; i < c.size(); ++i) {
        const Vec3& inertia = c.principal_inertia_kg_m2[i];
        const Vec3 w1 = c.omega[1][i];
        c.omega[2][i] += sign * 0.5 * w1.cross(inertia.cwiseProduct(w1)).cwiseQuotient(inertia);
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
    // The kept prediction holds the dynamic bodies only (GearPrediction): a
    // kinematic or fixed body's next x₀ and x₁ come from its stored ones,
    // this x₁ included. So prescribing a kinematic body's velocity at every
    // step (a column test's cap nodes, carried with the plate) keeps it.
    const Motion motion = w.of(b.kind()).motion[b.index()];
    if (motion != Motion::kinematic && motion != Motion::fixed) invalidate_prediction(w);
    w.of(b.kind()).x[1][b.index()] = v_m_per_s * w.dt_s;
}

void set_motion(World& w, BodyRef b, Motion motion)
{
    TranslationalState& body = w.of(b.kind());
    const std::uint32_t i = b.index();
    WIREDEM_ASSERT(body.motion[i] != Motion::clumped && motion != Motion::clumped, "a clump's sphere moves with its clump");
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
    WIREDEM_ASSERT(body.motion[i] != Motion::clumped, "a clump's sphere moves with its clump");
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
    for (Vec3& v : w.clumps.x[1]) v *= factor;
    for (Vec3& v : w.clumps.omega[1]) v *= factor;
    for (std::uint32_t i = 0; i < w.clumps.size(); ++i) place_clump_spheres(w, i, w.clumps.orientation[i]);
}

void invalidate_neighbours(World& w)
{
    w.neighbours_dirty = true;
}

} // namespace wiredem::engine
