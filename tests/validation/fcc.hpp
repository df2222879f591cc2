// Thornton's face-centred cubic array in the cuboid cell, as the validation
// test (test_thornton_fcc.cpp) and the figure's sweep (thornton_fcc_sweep.cpp)
// run it: one set-up in one place.
#pragma once

#include "scene.hpp"
#include "simulation.hpp"
#include "timestep.hpp"
#include "triaxial/cuboid.hpp"

#include <cstddef>
#include <string>

namespace wiredem::engine::validation {

/// Grains 10× softer than the paper's (E = 1 GPa: elastic strains of
/// 10⁻³ at σ₃ = 20 kPa, the geometric term small, and a larger δt).
inline const Material fcc_grain{1e9, 0.3, 7800.0};
inline constexpr double sigma3_pa = 20e3;

/// How the array is run.
struct FccOptions {
    int cells = 2;                         ///< unit cells along each axis (2: 63 spheres)
    Integrator integrator = Integrator::gear5;  ///< the reference
    /// Of the auto step. Half: at the auto step Gear-5 is unstable in this
    /// array's highest mode (each sphere has twelve neighbours, the auto step
    /// follows one pair's frequency): the walls' forces alternated from one
    /// step to the next, top against bottom by 3×, and the frictionless
    /// array "held" σ₁/σ₃ = 3.0 instead of 2 (docs/validation.md). At half
    /// the step Gear-5 gives Verlet's numbers (1.985 for both).
    double time_step_fraction = 0.5;
    /// Thornton's mechanism has no rotation (the uniform mode turns no
    /// sphere); free spheres find rolling modes and fail lower (measured
    /// 3.0 instead of 3.7 at μ = 0.3). Held: 1/I = 0.
    bool spins_held = true;
    /// k_t of the tangential law [1/m]; 0: the contact law's default.
    double tangential_stiffness_per_m = 0.0;
    /// γ_t of the tangential law's sliding branch [s/m]; 0: the law's default.
    double tangential_damping_s_per_m = 0.0;
};

/// The FCC array with friction μ between the spheres, frictionless walls.
inline CuboidWalls fcc_world(Simulation& sim, double mu, const FccOptions& o = {})
{
    World& w = sim.world;
    w = World{};
    w.gravity_m_per_s2 = Vec3::Zero(); // Thornton's array is weightless
    w.contact.tangential.friction_coeff = mu;
    if (o.tangential_stiffness_per_m > 0.0) w.contact.tangential.stiffness_per_m = o.tangential_stiffness_per_m;
    if (o.tangential_damping_s_per_m > 0.0) w.contact.tangential.damping_s_per_m = o.tangential_damping_s_per_m;
    FccArraySpec spec;
    spec.grain = fcc_grain;
    spec.cells = {o.cells, o.cells, o.cells};
    const CuboidWalls walls = build_fcc_array(w, spec);
    const double m = sphere_mass_kg(fcc_grain.density_kg_per_m3, spec.grain_radius_m);
    // e ≈ 0.5 for two grains meeting at 0.1 m/s: the default restitution.
    w.contact.normal_damping_s = hertz_damping_for_restitution_s(0.5, 0.5 * m, 0.1,
        effective_modulus_pa(fcc_grain.youngs_modulus_pa, fcc_grain.poisson_ratio, fcc_grain.youngs_modulus_pa,
            fcc_grain.poisson_ratio),
        0.5 * spec.grain_radius_m);
    set_time_step(w, o.time_step_fraction * stable_time_step(w).auto_s);
    set_integrator(w, o.integrator);
    if (o.spins_held)
        for (double& i : w.grain_rotation.inv_inertia_per_kg_m2) i = 0.0;
    return walls;
}

inline CuboidSettings fcc_settings()
{
    CuboidSettings s;
    s.triaxial.confining_pressure_pa = sigma3_pa;
    s.triaxial.target_axial_strain = 0.015;
    s.triaxial.plate_speed_m_per_s = 2e-3;       // ε̇ ≈ 0.2 /s: I ≈ 4·10⁻⁴
    s.triaxial.pressure_ramp_time_s = 0.01;
    s.triaxial.hold_time_s = 0.01;
    s.triaxial.sample_interval_s = 5e-5;
    s.triaxial.snapshot_strains = {};  // 0 and the target only, as before the job's defaults
    s.triaxial.consolidation = Consolidation::cell_pressure;
    return s;
}

struct FccRun {
    CuboidResult result;
    World world;               ///< at the end
    double peak_ratio = 0.0;   ///< largest σ₁/σ₃ over the loading rows
    std::size_t peak_row = 0;
    std::string error;         ///< the run's error, if it failed
};

inline FccRun run_fcc(double mu, unsigned threads = 1, const FccOptions& o = {}, const CuboidSettings& settings = fcc_settings())
{
    Simulation sim(threads);
    const CuboidWalls walls = fcc_world(sim, mu, o);
    auto r = run_cuboid_triaxial(sim, walls, settings);
    FccRun run;
    if (!r.ok()) {
        run.error = r.error();
        return run;
    }
    run.result = std::move(r.value());
    run.world = sim.world;
    const TriaxialSeries& s = run.result.triaxial.series;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s.phase[i] != static_cast<std::uint8_t>(TriaxialPhase::loading)) continue;
        const double ratio = s.sigma1_pa[i] / s.sigma3_effective_pa[i];
        if (ratio > run.peak_ratio) run.peak_ratio = ratio, run.peak_row = i;
    }
    return run;
}

} // namespace wiredem::engine::validation
