// Column specimens of the column-test suites (test_triaxial.cpp,
// test_free_standing.cpp), built directly (no pouring, which is slow): soft
// grains (E = 10⁸ Pa, so the stable δt is large) on a loose lattice with a
// little horizontal jitter and 5 % polydispersity, a rigid membrane just
// outside them (taller than the column, so that the cap seal is exercised),
// the bottom plate at z = 0 and the top plate touching the tallest grain;
// or a stack of grains on the axis.
#pragma once

#include "forces/membrane_forces.hpp"
#include "scene.hpp"
#include "simulation.hpp"
#include "step.hpp"
#include "timestep.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace wiredem::engine::test {

inline constexpr double grain_radius_m = 1.23e-3;
inline const Material soft_grain{1e8, 0.3, 7800.0};
inline const Material plate{1e9, 0.3, 7800.0};

/// Membrane of the tests: 10× softer than the model's sheet (E_m = 10⁷ Pa,
/// rubber-like, so that its hoop tension carries a small part of σ₃ and the
/// grains feel most of it) and 100× heavier so that it does not set δt.
inline MembraneSpec test_membrane(double radius_m, double height_m)
{
    MembraneSpec m;
    m.radius_m = radius_m;
    m.height_m = height_m;
    m.youngs_modulus_pa = 3e7;
    m.density_scale = 100.0;
    return m;
}

/// Sets δt to the auto fraction of the critical step of the deformable system.
inline void set_auto_time_step(World& w)
{
    set_time_step(w, stable_time_step(stability_inputs(w, MembraneAs::deformable)).auto_s);
}

/// Zeroes every body's motion and restarts the Gear derivatives from the
/// current forces.
inline void bring_to_rest(Simulation& sim)
{
    for (auto& body : sim.world.bodies)
        for (int k = 1; k < gear_order; ++k)
            for (auto& x : body.x[k]) x.setZero();
    for (int k = 1; k < gear_order; ++k)
        for (auto& x : sim.world.grain_rotation.theta[k]) x.setZero();
    begin_run(sim.world, sim.pool());
}

/// The specimen of the file comment, in layers 2.1 mm apart: a ring of grains
/// touching the membrane (alternate rings turned by half a spacing) around a
/// body-centred lattice. Settled for 3 ms under 10 g, brought to rest, then
/// the top plate is placed on the tallest grain. Returns the top plate's wall
/// index. `membrane_radius_m`: 8 mm (the tests' column, six and a half grain
/// radii) or wider (the collapse benchmark's).
inline std::size_t build_lattice_specimen(Simulation& sim, int layers = 9, double membrane_radius_m = 8e-3)
{
    World& w = sim.world;
    w = World{};
    w.contact.normal_damping_s = 5e-5; // strong: ≈ 0.3 of critical at the typical overlap
    const std::uint8_t grain_mat = add_material(w, soft_grain);
    const std::uint8_t plate_mat = add_material(w, plate);
    add_wall(w, make_plate(0.0, +1.0, plate_mat));

    const double r = grain_radius_m;
    const double membrane_contact_m = 0.5e-3;
    const double ring_m = membrane_radius_m - membrane_contact_m - r; // ring grains touch the membrane spheres
    const auto ring_count = static_cast<int>(2.0 * std::numbers::pi * ring_m / (2.04 * r));
    const double jitter = 0.03 * r;
    const double a = 2.0 * r + 2.0 * jitter;          // horizontal lattice spacing: no overlaps in a layer
    const double layer_m = 2.1e-3;                    // ≥ what rings turned by half a spacing need
    const double interior_m = ring_m - 2.04 * r - 2.0 * jitter;
    // Lattice sites ±n spacings from the axis: enough to reach the interior's edge.
    const int n = std::max(4, static_cast<int>(std::ceil(interior_m / a)) + 1);
    SplitMix64 rng(7);
    for (int k = 0; k < layers; ++k) {
        const double z = r + k * layer_m;
        for (int i = 0; i < ring_count; ++i) {
            const double phi = 2.0 * std::numbers::pi * (i + 0.5 * (k % 2)) / ring_count;
            add_grain(w, Vec3(ring_m * std::cos(phi), ring_m * std::sin(phi), z), r, grain_mat);
        }
        const double shift = k % 2 ? 0.5 * a : 0.0;   // body-centred: odd layers sit in the pockets
        for (int i = -n; i <= n; ++i)
            for (int j = -n; j <= n; ++j) {
                const double x = i * a + shift, y = j * a + shift;
                if (std::hypot(x, y) > interior_m) continue;
                // One draw per statement (engine/scene.cpp says why).
                const double radius = r * (1.0 - 0.05 * rng.uniform());
                const double dy = jitter * (2.0 * rng.uniform() - 1.0);
                const double dx = jitter * (2.0 * rng.uniform() - 1.0);
                add_grain(w, Vec3(x + dx, y + dy, z), radius, grain_mat);
            }
    }
    const double column_top_m = r + (layers - 1) * layer_m + r;
    build_membrane(w, test_membrane(membrane_radius_m, column_top_m + 3e-3));
    set_membrane_rigid(w, true);
    set_auto_time_step(w);

    // Settle under 10 g (the membrane rigid, no lid), then at rest under g.
    w.gravity_m_per_s2 = Vec3(0.0, 0.0, -100.0);
    for (double t = 0.0; t < 3e-3; t += w.dt_s) sim.step();
    w.gravity_m_per_s2 = Vec3(0.0, 0.0, -10.0);
    bring_to_rest(sim);
    double top = 0.0;
    const TranslationalState& g = w.of(BodyKind::grain);
    for (std::size_t i = 0; i < g.size(); ++i) top = std::max(top, g.x[0][i].z() + g.radius_m[i]);
    return add_wall(w, make_plate(top, -1.0, plate_mat));
}

/// Grains in the stack of build_grain_stack.
inline constexpr int stack_grains = 5;

/// A stack of `stack_grains` grains on the axis, touching, on the bottom plate,
/// with strong contact damping; a rigid membrane of radius 8 mm around it,
/// far away (it touches nothing); the top plate `press_m` into the top grain.
/// Returns the top plate's wall index.
inline std::size_t build_grain_stack(Simulation& sim, double press_m, MembraneEdgeLaw edges = MembraneEdgeLaw::tension_only)
{
    World& w = sim.world;
    w.contact.normal_damping_s = 5e-5;
    const std::uint8_t grain_mat = add_material(w, soft_grain);
    const std::uint8_t plate_mat = add_material(w, plate);
    add_wall(w, make_plate(0.0, +1.0, plate_mat));
    const double r = grain_radius_m, top_m = 2.0 * r * stack_grains;
    for (int k = 0; k < stack_grains; ++k) add_grain(w, Vec3(0, 0, r + 2.0 * r * k), r, grain_mat);
    MembraneSpec membrane = test_membrane(8e-3, top_m + 2e-3);
    membrane.edges = edges;
    build_membrane(w, membrane);
    set_membrane_rigid(w, true);
    const std::size_t top = add_wall(w, make_plate(top_m - press_m, -1.0, plate_mat));
    set_auto_time_step(w);
    return top;
}

} // namespace wiredem::engine::test
