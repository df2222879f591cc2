// Small builders shared by the engine tests.
#pragma once

#include "simulation.hpp"
#include "state/world.hpp"

#include <cmath>
#include <numbers>

namespace wiredem::engine::test {

/// Mass of a solid sphere [kg].
inline double sphere_mass_kg(double radius_m, double density_kg_per_m3)
{
    return density_kg_per_m3 * 4.0 / 3.0 * std::numbers::pi * radius_m * radius_m * radius_m;
}

/// A world without gravity, one material, the given damping, δt.
inline void reset_world(World& w, const Material& m, double dt_s, double damping_s = 0.0)
{
    w = World{};
    w.gravity_m_per_s2 = Vec3::Zero();
    w.dt_s = dt_s;
    w.contact.normal_damping_s = damping_s;
    add_material(w, m);
}

} // namespace wiredem::engine::test
