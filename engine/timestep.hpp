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

#include "parallel/thread_pool.hpp"
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

/// Gear-5 with a damping force −c v on a mass m is stable only while
/// c δt / m stays below about 0.16, whatever the stiffness: on a damped
/// harmonic oscillator (damping ratio ζ = c / (2 m ω)) it grows without
/// bound from ω δt ζ = 0.069 at ζ = 0.22, 0.074 at ζ = 0.3, 0.078 at 0.5,
/// 0.081 at 1 and 0.082 at 20 (c δt/m = 2 ζ ω δt; tests/engine/test_gear5.cpp).
/// The critical step of a damped oscillation is the smaller of
/// gear5_stability_limit / ω and this over c/m: ω δt ≤ min(0.3, 0.065 / ζ),
/// 5–20 % inside the measured bound. Velocity Verlet's exact bound is
/// ω δt ≤ 2 (√(1 + ζ²) − ζ) (the same test); it is used with the accuracy
/// bound gear5_stability_limit above.
inline constexpr double gear5_damping_limit = 0.13;

/// Largest ω δt of an oscillation of damping ratio ζ that `integrator` keeps
/// bounded, with the margins above (gear5_stability_limit when ζ = 0).
[[nodiscard]] double damped_stability_limit(Integrator integrator, double damping_ratio);

/// Fraction of the undamped critical step used by `auto`: ω δt = 0.15, about
/// 40 steps per period of the stiffest oscillation (a Hertz collision at the
/// reference overlap takes ≳ 20 steps, a gentler one more), with an energy
/// drift of the undamped oscillator below 10⁻³ over 2·10⁵ steps. `auto` never
/// exceeds the damped critical step either (StableStep::auto_s): damping does
/// not ask for more steps per period, it lowers the ceiling (a restitution of
/// 0.2 or less blew Gear-5 up at ω δt = 0.15).
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
    /// γ_n of the contact law: a contact of tangent stiffness K = dF/dξ on a
    /// mass m has the damping ratio ζ = ω γ_n / 3, ω = √(K/m) [s]
    double normal_damping_s = 0.0;
    Integrator integrator = Integrator::gear5;      ///< whose bound applies (damped_stability_limit)
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
    double critical_s = 0.0;   ///< largest stable δt, damping included [s]
    /// The same without damping: gear5_stability_limit over the highest ω [s]
    double undamped_critical_s = 0.0;
    /// What `auto` uses: auto_time_step_fraction × undamped_critical_s, or
    /// critical_s where damping brings that lower [s]
    double auto_s = 0.0;
    std::string limited_by;    ///< what sets critical_s, e.g. "wire segments", "grain–grain contacts"

    /// Whether damping brings the critical step below
    /// min_damped_step_fraction of the undamped one (overdamped_error).
    [[nodiscard]] bool overdamped() const;
};

/// Damping may lower the critical step to this fraction of the undamped one;
/// below it a run is refused (overdamped_error) instead of taking more than
/// ten times the steps its work was estimated at (the estimate made at
/// validation leaves a restitution's damping out: api/derived.hpp) or, for
/// a damping without bound, a time without bound.
inline constexpr double min_damped_step_fraction = 0.1;

/// What to tell a run whose step `s` is overdamped (StableStep::overdamped),
/// whose contacts have normal damping `normal_damping_s`.
[[nodiscard]] std::string overdamped_error(const StableStep& s, double normal_damping_s);

/// Critical δt from every kind of contact the inputs allow (lightest body,
/// stiffest material pair, smallest radius of each kind; body–wall contacts),
/// damped by γ_n, and from the springs: the highest chain mode of the wire,
/// ω² = 4 k_elo/m_w, damped by its ratio, and a membrane node's six edges,
/// bounded (Gershgorin) by ω² ≤ 12 k_m/m_m.
/// @param impact_speed_m_per_s  fastest expected impact: the Hertz stiffness is
///        taken at the larger of the reference overlap and the maximum overlap
///        of a collision at this speed (heavy, density-scaled grains falling
///        at real speeds overlap far more than 2 %).
[[nodiscard]] StableStep stable_time_step(const StabilityInputs& in, double impact_speed_m_per_s = 0.0);

/// The stable step of a built system: stable_time_step(stability_inputs(w), …).
[[nodiscard]] StableStep stable_time_step(const World& w, double impact_speed_m_per_s = 0.0);

/// The stiffest contact touching now, and the step it allows: what
/// stable_time_step says of a contact, at the contact's own overlap instead
/// of the one expected (docs/model.md, "The stiffest live contact"). The
/// Hertz stiffness grows as √ξ, so a soft column pressed far beyond the
/// reference overlap needs a shorter step than the one it was given.
struct LiveContactLimit {
    /// Largest stable δt of the touching contacts, damping included:
    /// damped_stability_limit(ζ)/ω of the one that allows the least;
    /// infinity with no contact on a moving body [s]
    double critical_s = std::numeric_limits<double>::infinity();
    double overlap_m = 0.0;           ///< that contact's overlap ξ [m]
    double stiffness_n_per_m = 0.0;   ///< its tangent stiffness dF/dξ = 2 E* √(R* ξ) [N/m]
    double mass_kg = 0.0;             ///< the lighter moving body of its two [kg]
    /// Its reference overlap, reference_overlap_fraction × R* (R* from the
    /// contact's prefactor: (4/3) E* √R* with E* = stiffness²/(4 R* ξ)) [m]
    double reference_overlap_m = 0.0;
    std::string kinds;                ///< "grain–grain", "grain–wall", …
};

/// The stiffest live contact of `w` (LiveContactLimit): every touching
/// contact of the list with a moving side, its tangent stiffness
/// (3/2) · (4/3) E* √R* · √ξ from the list's prefactor and this step's
/// overlap, on the lighter moving body (a clump's sphere with the mass its
/// contacts see), as stable_time_step takes a contact. A pass over the
/// contacts: cheap next to a step, and run every live_check_steps. On
/// `pool`'s threads over fixed blocks (reduce_blocks), the stiffest of each
/// block taken in block order with the first of equals kept: the contact the
/// serial pass finds, on any thread count.
[[nodiscard]] LiveContactLimit live_contact_limit(const World& w, ThreadPool& pool);
/// The same on the calling thread alone.
[[nodiscard]] LiveContactLimit live_contact_limit(const World& w);

/// How often a column test checks its stiffest live contact [steps]: a pass
/// over the contact list, a sqrt and a division per touching contact, every
/// 10 steps (the step's contact kernel makes the same pass with far more
/// work). Every 100 was too seldom: the lattice column ramped to 10 MPa in
/// 5 ms went from 0.54 of the limit to NaN between two checks.
inline constexpr std::uint64_t live_check_steps = 10;

/// How far beyond the live limit a column test steps before it is stopped:
/// δt > live_contact_tolerance × LiveContactLimit::critical_s. The limit
/// keeps the 5–20 % margin of damped_stability_limit; Gear-5 diverges
/// beyond it, on the damped oscillator at 1.14–1.26 times it (ω δt ζ =
/// 0.074 at ζ = 0.3, 0.078 at 0.5, 0.081 at 1, against 0.065; undamped
/// 0.35 against 0.3), but a contact pressed that far is transient and the
/// growth slow. Measured in column tests (docs/model.md, "The stiffest live
/// contact"): runs that ended held up to 1.40 (examples/tiny-gravel.json's
/// second test; tests/web/job-breaks.json 1.152; the lattice column at
/// 200 kPa 1.14); runs that blew up held 1.2–1.7 for tens to 1 200 steps
/// and then ran away, 2.3–4.8 at their last check before NaN. 1.5 lets
/// every run that ended end and stops every one that blew up, at the check
/// where it runs away at the latest, with finite values.
inline constexpr double live_contact_tolerance = 1.5;

/// What to tell a run whose step `dt_s` exceeds the live limit `live` by more
/// than live_contact_tolerance, `after` saying when ("after 1200 steps of
/// the triaxial test"): the contact, its overlap against the reference, and
/// the fields to change.
[[nodiscard]] std::string live_contact_error(const LiveContactLimit& live, double dt_s, const std::string& after);

} // namespace wiredem::engine
