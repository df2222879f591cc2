// The rigid-wall triaxial cell (issue 43; docs/model.md, "The rigid-wall
// cell"): a cuboid of six rigid plane walls around the specimen instead of
// the membrane. The bottom wall is fixed; the four lateral walls are servo
// walls that hold σ₃ (as YADE's TriaxialStressController and PFC's servo
// walls do); the top wall first follows the consolidation target like the
// membrane cell's cap, then moves down at the constant plate speed. It runs
// the membrane cell's phases (triaxial/pressure.hpp: the σ₃ ramp;
// consolidation.hpp: the window, the mismatch, the target; loading.hpp:
// ColumnTestStepper and load_to_target; sampling.hpp: the rows, snapshots,
// the quasi-static verdict) and its readings (read_loading: peak, yield,
// verdict), so its results are those of a membrane test.
//
// The servo (PFC's, with the contacts' dashpots): each step a lateral wall
// moves along its inward normal at v = α e / (k_w δt + c_w), e = A (σ₃ −
// σ_wall) the force error, A the wall's face, k_w = Σ dF_n/dξ and c_w =
// Σ dF_n/d(dξ/dt) over its touching contacts (Hertz with damping: (3/2) c √ξ
// and c γ_n √ξ), α the relaxation factor. With the grains behind the
// contacts held (the stiffest case: they give way too, springs in series),
// a wall moving at v_n changes the force by k_w v_n δt + c_w (v_n − v_{n−1}),
// so the error obeys e_n = (1 − α) e_{n−1} + α β e_{n−2}, β = c_w/(k_w δt +
// c_w) ∈ [0, 1): both roots of z² − (1 − α) z − α β lie inside the unit
// circle for α < 2/(1 + β), i.e. for every α ≤ 1 whatever the damping; the
// default α = 0.5 is PFC's. (PFC's gain α A/(k_w δt) leaves c_w out: with
// the tests' damping, c_w is 5 k_w δt, and that gain oscillated from one
// step to the next between its speed limits.) The wall has no mass (its
// velocity is prescribed each step: kinematic), and |v| is capped at
// max_piston_speed_factor × the plate speed, as the membrane cell's piston
// (a wall that loses its last contact would otherwise have no bound).
//
// Stresses from the walls (compression positive): σ₁ = F_top / (L_x L_y),
// σ_x = mean of the two x walls' forces / (L_y h), σ_y likewise, and the
// cell's σ₃ (sigma3_effective_pa of a row) = (σ_x + σ_y)/2. A row's
// column_radius_m is the equivalent radius √(L_x L_y / π), so that the
// membrane cell's formulas (σ₁ = F/(π r²), V = π r² h) give the box's.
//
// Determinism: every sum is a serial loop in contact order or a
// reduce_blocks over canonical order: bit-identical for any thread count.
#pragma once

#include "core/result.hpp"
#include "simulation.hpp"
#include "triaxial/triaxial.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace wiredem::engine {

/// The six walls of a cuboid cell, as indices into World::walls.
struct CuboidWalls {
    std::size_t bottom = 0;              ///< normal +z, fixed
    std::size_t top = 0;                 ///< normal −z, the loading platen
    /// x_min (normal +x), x_max (−x), y_min (+y), y_max (−y).
    std::array<std::size_t, 4> lateral{};
};

/// Adds the six plane walls of the box [lo, hi] (normals inwards), of
/// material `material`, each with the friction coefficient `friction_coeff`
/// (nullopt: the contact law's μ; 0: frictionless). Returns their indices.
CuboidWalls add_cuboid_walls(World& w, const Vec3& lo_m, const Vec3& hi_m, std::uint8_t material,
    std::optional<double> friction_coeff);

/// The servo's relaxation factor α by default (PFC's choice).
inline constexpr double default_servo_relaxation = 0.5;

/// How the force of a wall's touching contacts answers its motion.
struct WallResponse {
    double stiffness_n_per_m = 0.0;   ///< k_w = Σ dF_n/dξ = Σ (3/2) c √ξ [N/m]
    double damping_n_s_per_m = 0.0;   ///< c_w = Σ dF_n/d(dξ/dt) = Σ c γ_n √ξ [N·s/m]
};

/// k_w and c_w over the touching contacts of `wall` in the last step (c the
/// contact's Hertz coefficient), in contact order.
[[nodiscard]] WallResponse wall_response(const World& w, std::size_t wall);

/// A servo wall's speed along its inward normal [m/s] (> 0: towards the
/// specimen): α (σ_target − σ_wall) A / (k_w δt + c_w), capped at
/// ±max_speed; +max_speed when the wall touches nothing and is below target.
/// @param target_pa, measured_pa  σ₃ to hold and the wall's stress [Pa]
/// @param area_m2                 the wall's face A [m²], > 0
/// @param relaxation              α ∈ (0, 1]
[[nodiscard]] double servo_wall_speed_m_per_s(double target_pa, double measured_pa, double area_m2,
    const WallResponse& response, double dt_s, double relaxation, double max_speed_m_per_s) noexcept;

/// The box and the stresses its walls carry, after the last step.
struct CuboidStresses {
    double width_x_m = 0.0, width_y_m = 0.0, height_m = 0.0; ///< L_x, L_y, h [m]
    double sigma_x_pa = 0.0;   ///< mean force of the x walls / (L_y h) [Pa]
    double sigma_y_pa = 0.0;   ///< mean force of the y walls / (L_x h) [Pa]
    double sigma_z_pa = 0.0;   ///< top wall force / (L_x L_y) [Pa]
    /// Each lateral wall's stress, in CuboidWalls::lateral's order [Pa].
    std::array<double, 4> lateral_pa{};
    std::size_t lateral_contacts = 0; ///< bodies touching the lateral walls
};
[[nodiscard]] CuboidStresses cuboid_stresses(const World& w, const CuboidWalls& walls);

/// The stress of the specimen from its contacts (Love–Weber), compression
/// positive [Pa]: σ = −(1/V) [Σ_pairs (x_b − x_a) ⊗ F_a + Σ_wall contacts
/// (x_c − x_g) ⊗ F_g], F_a the force on the pair's first body, x_c the
/// contact point on the wall's surface (at r − ξ from the centre). For a
/// specimen at rest (no net force on any body) it equals the walls' stress
/// of cuboid_stresses with V = L_x L_y h; otherwise they differ by
/// (1/V) Σ_bodies x ⊗ F_net (love_weber_inertia_bound_pa bounds it).
[[nodiscard]] Eigen::Matrix3d love_weber_stress_pa(const World& w, double volume_m3);

/// (1/V) Σ_bodies |x − x₀| |F_net| [Pa], x₀ the bodies' centroid: how far
/// the contacts' stress may be from the walls' because the bodies are not
/// at rest (F_net the net force of the last step on each moving body).
[[nodiscard]] double love_weber_inertia_bound_pa(const World& w, double volume_m3);

/// Parameters of a test in the cuboid cell.
struct CuboidSettings {
    /// Every membrane-cell parameter, with the same meaning and range
    /// (σ₃ is what the lateral walls hold; plate_speed_m_per_s the top wall's).
    TriaxialSettings triaxial;
    double servo_relaxation = default_servo_relaxation; ///< α ∈ (0, 1]
};

/// Checks the settings: an error naming the field, its value and the range.
[[nodiscard]] std::optional<std::string> validate_cuboid_settings(const CuboidSettings& s);

/// What a cuboid test produced: a membrane test's result, and per row the
/// box and its lateral stresses.
struct CuboidResult {
    TriaxialResult triaxial;
    std::vector<double> width_x_m, width_y_m;   ///< per row of triaxial.series [m]
    std::vector<double> sigma_x_pa, sigma_y_pa; ///< per row [Pa]
    /// The servo's accuracy over the loading rows: the largest and the mean
    /// |σ_x − σ₃|/σ₃ and |σ_y − σ₃|/σ₃.
    double servo_max_deviation = 0.0;
    double servo_mean_deviation = 0.0;
};

/// Everything of a cuboid test that changes from step to step outside the
/// World: the membrane cell's driver state (its result holds the rows and
/// snapshots so far; cap_nodes stays empty) and per row the box and its
/// lateral stresses. A checkpoint saves it beside the World.
struct CuboidDriverState {
    TriaxialDriverState triaxial;
    std::vector<double> width_x_m, width_y_m;   ///< per row of triaxial.result.series [m]
    std::vector<double> sigma_x_pa, sigma_y_pa; ///< per row [Pa]
};

/// How a host checkpoints a cuboid test and continues one (as TriaxialContinuation).
struct CuboidContinuation {
    /// Called between every two steps of this run, and just before it returns
    /// because it was cancelled: a consistent point to save the World and the state.
    std::function<void(const World&, const CuboidDriverState&)> between_steps;
    /// When set, the test continues from this state; sim.world must be the
    /// World saved with it. The result, and the World at the end, are
    /// bit-identical to those of a test that was never stopped.
    std::optional<CuboidDriverState> from;
};

/// Runs one test in the cuboid cell on `sim.world` (grains, no membrane, the
/// six walls `walls`, δt set), leaving the World in its final state.
/// RunControl as run_triaxial's; checkpoints and continuation as
/// run_triaxial's (CuboidContinuation).
/// @return the result, or an error: settings out of range, walls missing or
///         misplaced, a membrane present, δt above the stable step, a saved
///         state that does not fit, cancelled, blew up.
[[nodiscard]] Result<CuboidResult, std::string> run_cuboid_triaxial(Simulation& sim, const CuboidWalls& walls,
    const CuboidSettings& settings, const RunControl& control = {}, CuboidContinuation continuation = {});

} // namespace wiredem::engine
