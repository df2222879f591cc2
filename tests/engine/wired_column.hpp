// A small column with every kind of body and contact memory, built directly
// (no pouring): soft grains in four pressed lattice layers, a wire ring laid
// in a gap between the second and third layer, a deformable membrane under pressure
// around them, the bottom plate and a top plate pressing down at a prescribed
// speed. The grains start with random velocities and the column settles
// under gravity and the plate: after ~900 steps (2.6 ms) about 190 pairs and
// 20 wall contacts touch, a fifth to a half of them sliding, the top plate
// presses on ~8 grains and the wire ring, bent beyond its joints' yield
// angle, keeps yielding (tests/engine/test_snapshot.cpp checks this). Used where a test
// needs a column mid-test cheaply: snapshot round trips, hash determinism.
#pragma once

#include "forces/membrane_forces.hpp"
#include "forces/wire_forces.hpp"
#include "scene.hpp"
#include "simulation.hpp"
#include "timestep.hpp"

#include <cmath>
#include <numbers>

namespace wiredem::engine::test {

/// Builds the column into `w` (replacing it) with the given integrator; δt is
/// the auto step. Returns the top plate's wall index.
inline std::size_t build_wired_column(World& w, Integrator integrator)
{
    w = World{};
    w.integrator = integrator;
    w.contact.normal_damping_s = 2e-5;
    w.contact.tangential.friction_coeff = 0.5;
    const double r = 1e-3;                                              // grain radius
    const std::uint8_t grain_mat = add_material(w, Material{1e8, 0.3, 2600.0}); // soft: a large δt
    const std::uint8_t plate_mat = add_material(w, Material{1e9, 0.3, 7800.0});
    add_wall(w, make_plate(0.0, +1.0, plate_mat));

    WireSpec wire;
    wire.density_scale = 1e4; // so that the wire does not set δt
    configure_wire(w, wire);
    const double wire_gap_m = 2.0 * wire.radius_m + 0.2e-3;

    // Simple-cubic layers of touching grains, the lowest on the floor; the
    // wire's gap between the second and the third layer.
    const double a = 2.0 * r;
    double z = r, wire_z = 0.0;
    for (int layer = 0; layer < 4; ++layer) {
        for (int i = -2; i <= 2; ++i)
            for (int j = -2; j <= 2; ++j)
                if (std::hypot(i * a, j * a) < 4.5e-3) add_grain(w, Vec3(i * a, j * a, z), r, grain_mat);
        if (layer == 1) {
            wire_z = z + r + 0.5 * wire_gap_m;
            z += wire_gap_m;
        }
        z += a;
    }
    const double top_m = z - a + r; // the top of the highest layer
    // An open ring of radius 3.6 mm, 300° long: its joints are bent by l_w/R,
    // three times the yield angle ε_y l_w / r_w of the default wire.
    const double ring_m = 3.6e-3;
    const auto nodes = static_cast<int>((300.0 / 360.0) * 2.0 * std::numbers::pi * ring_m / wire.segment_length_m);
    for (int n = 0; n < nodes; ++n) {
        const double phi = n * wire.segment_length_m / ring_m;
        append_wire_node(w, Vec3(ring_m * std::cos(phi), ring_m * std::sin(phi), wire_z));
    }

    MembraneSpec membrane;
    // The outer grains (at 4.5 mm) 30 µm from the node spheres; the top row
    // just below the top plate, which would push rows above it down.
    membrane.radius_m = 6.0e-3;
    membrane.height_m = top_m - membrane.contact_radius_m - 0.1e-3;
    membrane.youngs_modulus_pa = 1e7;
    membrane.density_scale = 100.0;
    build_membrane(w, membrane);
    set_membrane_rigid(w, false);
    w.membrane.pressure_pa = 10e3;

    // The top plate 20 µm into the highest grains, moving down at 0.1 m/s.
    Wall top = make_plate(top_m - 20e-6, -1.0, plate_mat);
    top.velocity_m_per_s = Vec3(0.0, 0.0, -0.1);
    const std::size_t top_wall = add_wall(w, top);

    w.dt_s = stable_time_step(w).auto_s; // every body is at rest: no derivative to rescale
    SplitMix64 rng(11);
    for (std::uint32_t i = 0; i < w.of(BodyKind::grain).size(); ++i) {
        // z, y, x: one draw per statement, in the order GCC evaluated the
        // arguments of Vec3(…) when they were drawn inside it (engine/scene.cpp).
        const double vz = 0.1 * rng.uniform() - 0.05;
        const double vy = 0.1 * rng.uniform() - 0.05;
        const double vx = 0.1 * rng.uniform() - 0.05;
        set_velocity(w, {BodyKind::grain, i}, Vec3(vx, vy, vz));
    }
    return top_wall;
}

} // namespace wiredem::engine::test
