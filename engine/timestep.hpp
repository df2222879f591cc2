// The stable time step (model spec §4). An explicit integrator is stable while
// ω δt stays below a method-dependent bound, ω = √(k/m) the highest natural
// frequency present. For Hertz contacts k grows with the overlap, so it is
// evaluated at a reference overlap (a fraction of the effective radius that no
// sound packing exceeds).
#pragma once

#include "state/world.hpp"

#include <string>

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

/// The highest frequency in the system and where it comes from.
struct CriticalStep {
    double critical_s = 0.0;   ///< largest stable δt [s]
    std::string limited_by;    ///< e.g. "grain–grain contacts"
};

/// Critical δt from every kind of contact that can occur in `w` (lightest body,
/// stiffest material pair, smallest radius of each kind) and from the wire's
/// and the (deformable) membrane's springs.
/// @param impact_speed_m_per_s  fastest expected impact: the Hertz stiffness is
///        taken at the larger of the reference overlap and the maximum overlap
///        of a collision at this speed (heavy, density-scaled grains falling
///        at real speeds overlap far more than 2 %).
[[nodiscard]] CriticalStep critical_time_step(const World& w, double impact_speed_m_per_s = 0.0);

/// Folds in a spring-type limit: ω² = k/m for a stiffness k [N/m] on a mass m [kg].
void fold_spring_limit(CriticalStep& c, double omega2_per_s2, const std::string& what);

} // namespace wiredem::engine
