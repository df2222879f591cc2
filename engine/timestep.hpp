// The stable time step (model spec §4). An explicit integrator is stable while
// ω δt stays below a method-dependent bound, ω = √(k/m) the highest natural
// frequency present. For Hertz contacts k grows with the overlap, so it is
// evaluated at a reference overlap (a fraction of the effective radius that no
// sound packing exceeds).
//
// One computation, two sources of inputs: stability_inputs(World) reads a
// built system, api::stability_inputs(JobSpec) estimates one from a job
// before any World exists; both feed stable_time_step(StabilityInputs), the
// only place that turns inputs into a step and the only place that applies
// auto_time_step_fraction.
#pragma once

#include "state/world.hpp"

#include <limits>
#include <string>
#include <vector>

namespace wiredem::engine {

/// Largest ω δt for which Gear-5 (with the corrector coefficients in gear5.hpp)
/// is stable on an undamped harmonic oscillator: bounded over 2·10⁵ steps at
/// 0.3, growing without bound from 0.35 (checked by
/// tests/engine/test_gear5.cpp). The critical step is this over ω.
///
/// Velocity Verlet is stable up to ω δt = 2 (tests/engine/test_verlet.cpp), but
/// the same bound is used for it: a Hertz collision at ω δt = 0.3 already
/// spans only ~10 steps, and both integrators resolve a collision equally well
/// at a given δt (contact time within 5 % and energy within 1 % at the auto
/// step: HertzCollision tests for both). Verlet's gain is a cheaper step.
inline constexpr double gear5_stability_limit = 0.3;

/// Fraction of the critical step used by `auto`: ω δt = 0.15, about 40 steps
/// per period of the stiffest oscillation (a Hertz collision at the reference
/// overlap takes ≳ 20 steps, a gentler one more), with an energy drift of the
/// undamped oscillator below 10⁻³ over 2·10⁵ steps.
inline constexpr double auto_time_step_fraction = 0.5;

/// Reference overlap for the Hertz stiffness, as a fraction of R*.
inline constexpr double reference_overlap_fraction = 0.02;

/// What bounds the step: for each kind of body the lightest moving body, the
/// smallest radius and the stiffest material; which kinds touch; the walls'
/// materials; the springs of the wire and of a deformable membrane.
struct StabilityInputs {
    /// Extremes over the bodies of one kind.
    struct Kind {
        bool present = false;   ///< at least one body of this kind exists
        bool moving = false;    ///< at least one of them is integrated (not held)
        double min_mass_kg = std::numeric_limits<double>::infinity();   ///< lightest moving body [kg]
        double min_radius_m = std::numeric_limits<double>::infinity();  ///< smallest body, held or not [m]
        double max_plane_modulus_pa = 0.0;  ///< stiffest E/(1−ν²), held or not [Pa]

        /// Folds in one body.
        void include(double mass_kg, bool held, double radius_m, double plane_modulus_pa);
    };
    std::array<Kind, body_kind_count> kinds{};
    KindMatrix kinds_interact = default_kinds_interact;
    std::vector<double> wall_plane_moduli_pa;       ///< E/(1−ν²) of every wall, in wall order [Pa]
    double wire_segment_stiffness_n_per_m = 0.0;    ///< k_elo; 0 without a wire of two nodes or more
    double wire_node_mass_kg = 0.0;                 ///< m_w
    double membrane_edge_stiffness_n_per_m = 0.0;   ///< k_m; 0 when the membrane is rigid or absent
    double membrane_node_mass_kg = 0.0;             ///< lightest node mass of the deformable membrane
};

/// How stability_inputs(World) treats the membrane.
enum class MembraneAs : std::uint8_t {
    is,          ///< as the World holds it (a rigid membrane's nodes are held and its edges idle)
    deformable,  ///< as set_membrane_rigid(w, false) would make it: the triaxial test's system
};

/// The inputs of the bodies, walls, wire and membrane of `w`.
[[nodiscard]] StabilityInputs stability_inputs(const World& w, MembraneAs membrane = MembraneAs::is);

/// The stable time step and where it comes from.
struct StableStep {
    double critical_s = 0.0;   ///< largest stable δt [s]
    double auto_s = 0.0;       ///< what `auto` uses: auto_time_step_fraction × critical_s [s]
    std::string limited_by;    ///< what sets critical_s, e.g. "wire segments", "grain–grain contacts"
};

/// Critical δt from every kind of contact the inputs allow (lightest body,
/// stiffest material pair, smallest radius of each kind; body–wall contacts)
/// and from the springs: the highest chain mode of the wire, ω² = 4 k_elo/m_w,
/// and a membrane node's six edges, bounded (Gershgorin) by ω² ≤ 12 k_m/m_m.
/// @param impact_speed_m_per_s  fastest expected impact: the Hertz stiffness is
///        taken at the larger of the reference overlap and the maximum overlap
///        of a collision at this speed (heavy, density-scaled grains falling
///        at real speeds overlap far more than 2 %).
[[nodiscard]] StableStep stable_time_step(const StabilityInputs& in, double impact_speed_m_per_s = 0.0);

/// The stable step of a built system: stable_time_step(stability_inputs(w), …).
[[nodiscard]] StableStep stable_time_step(const World& w, double impact_speed_m_per_s = 0.0);

} // namespace wiredem::engine
