// The collapse of a column without wire, the benchmark of axisymmetric
// granular collapse (Lube, Huppert, Sparks & Hallworth, J. Fluid Mech. 508,
// 2004; Lajeunesse, Mangeney-Castelnau & Vilotte, Phys. Fluids 16, 2004):
// the lattice column of column_specimens.hpp (no wire) taken out of its
// formwork by the free-standing test's removal at a stated speed, settled on
// the bottom plate, and its deposit measured as the experiments measure
// theirs (engine::deposit). Shared by the CI test (test_free_standing.cpp,
// ColumnCollapse.*) and the sweep behind docs/validation.md's figure
// (tests/validation/collapse_sweep.cpp, scripts/collapse_figure.py).
#pragma once

#include "triaxial/free_standing.hpp"

#include "column_specimens.hpp"

#include <cmath>
#include <optional>
#include <string>

namespace wiredem::engine::test {

/// The scaling laws of Lube et al. (2004) for a column of radius Rᵢ and height
/// Hᵢ released quickly, a = Hᵢ/Rᵢ: the runout (r∞ − Rᵢ)/Rᵢ = 1.24 a below
/// a = 1.7 and 1.6 a^½ above; the final height H∞/Rᵢ = a below a = 0.74
/// (the top is not reached by the failure) and 0.88 a^⅙ above.
[[nodiscard]] inline double lube_runout(double a) { return a < 1.7 ? 1.24 * a : 1.6 * std::sqrt(a); }
[[nodiscard]] inline double lube_final_height(double a) { return a < 0.74 ? a : 0.88 * std::pow(a, 1.0 / 6.0); }

/// How a collapse is run.
struct CollapseCase {
    int layers = 9;                    ///< lattice layers (2.1 mm apart): the column's height
    double membrane_radius_m = 8e-3;   ///< the formwork's radius
    /// The release speed (the membrane's radius opening, the top plate
    /// rising) over the column's free-fall speed scale √(g Hᵢ): ≫ 1 is the
    /// experiments' quick lift, ≪ 1 a slow release.
    double release_speed_ratio = 5.0;
    double removal_distance_m = 3e-3;  ///< how far the formwork opens (more than a grain diameter)
    double max_settling_time_s = 0.4;  ///< the deposit is read at rest or at this time
    /// The deposit's edge holds this fraction of the grains (engine::deposit).
    double runout_fraction = 0.95;
    /// Rolling resistance μ_r (model §10; 0: the model's spheres, which roll
    /// on the plate) and its damping ratio η_r.
    double rolling_friction_coeff = 0.0;
    double rolling_damping_ratio = 0.3;
};

/// What a collapse gave.
struct CollapseOutcome {
    std::size_t grains = 0;
    double initial_height_m = 0.0;     ///< Hᵢ: the column's height before the removal (its highest grain's top)
    double initial_radius_m = 0.0;     ///< Rᵢ: its outermost grain edge before the removal (the tube's radius)
    double release_speed_m_per_s = 0.0;
    SettlingReading settling;
    Deposit deposit;
    [[nodiscard]] double aspect_ratio() const { return initial_height_m / initial_radius_m; }
    [[nodiscard]] double runout() const { return (deposit.runout_radius_m - initial_radius_m) / initial_radius_m; }
    [[nodiscard]] double final_height() const { return deposit.height_m / initial_radius_m; }
};

/// Builds the column of `c`, removes its formwork and measures the deposit
/// (the free-standing test's settling; its compression only places the top
/// plate, and its first snapshot, at strain 0, holds the deposit).
[[nodiscard]] inline Result<CollapseOutcome, std::string> run_collapse(const CollapseCase& c, unsigned threads = 1)
{
    Simulation sim(threads);
    const std::size_t lid = build_lattice_specimen(sim, c.layers, c.membrane_radius_m);
    World& w = sim.world;
    w.contact.rolling.friction_coeff = c.rolling_friction_coeff;
    w.contact.rolling.damping_ratio = c.rolling_friction_coeff > 0.0 ? c.rolling_damping_ratio : 0.0;
    // The column was built and settled without rolling resistance: its step
    // is the auto step of the World that collapses, rolling springs included
    // (springs_critical_step_s; unchanged at μ_r = 0).
    set_auto_time_step(w);
    const StandingColumn before = standing_column(w, 1.0, FreeStandingSettings{}.bulk_fraction);
    const TranslationalState& grains = w.of(BodyKind::grain);
    const double bottom_m = w.walls[0].point_m.z();
    const Deposit column = deposit(grains.x[0], grains.radius_m, bottom_m, 1.0);
    FreeStandingSettings s;
    const double g = -w.gravity_m_per_s2.z();
    const double v = c.release_speed_ratio * std::sqrt(g * before.top_m);
    s.removal_distance_m = c.removal_distance_m;
    s.removal_time_s = c.removal_distance_m / v;
    s.escape_distance_m = 1.0;                   // every grain counts: the deposit is measured from all
    s.settle_kinetic_energy_per_grain_j = 1e-9;
    s.max_settling_time_s = c.max_settling_time_s;
    s.max_height_loss = 0.1;
    s.plate_speed_m_per_s = 0.05;
    s.target_axial_strain = 1e-3;
    s.failure_drop = 1.0;
    s.sample_interval_s = 1e-3;
    auto r = run_free_standing(sim, lid, s);
    if (!r.ok()) return Err(r.error());
    if (r.value().snapshots.empty()) return Err(std::string("the compression took no snapshot"));
    const TriaxialSnapshot& at_rest = r.value().snapshots.front();
    CollapseOutcome o;
    o.grains = at_rest.grain_position_m.size();
    o.settling = r.value().settling;
    o.initial_height_m = column.height_m;
    o.initial_radius_m = column.max_radius_m;
    o.release_speed_m_per_s = v;
    o.deposit = deposit(at_rest.grain_position_m, at_rest.grain_radius_m, bottom_m, c.runout_fraction);
    return o;
}

} // namespace wiredem::engine::test
