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

/// How many sticking contacts act on one body together, for the tangential
/// and rolling springs' step: a dense random packing's coordination. Each
/// contact's springs are taken alone (`tangential_omega2` on one side), but
/// in a packing all of a grain's contacts turn and shift it at once, and
/// that mode is up to √z times faster than one contact's (z K a²/I for its
/// rotation against z neighbours held). A pour of 4000 grains of 4 mm
/// (E = 10 GPa, masses × 100) blew up at one contact's ω δt = 0.273 (in its
/// pour) and 0.235 (settling after it), and ran 200 000 steps at 0.188:
/// √6 × 0.235 = 0.58, the engine spring's own bound (springs_stability_limit),
/// where one contact alone was judged safe up to 0.57 (docs/model.md, "The
/// tangential and rolling springs in the step").
inline constexpr double springs_coordination = 6.0;

/// ω δt of the springs' fastest mode in a packing, √(springs_coordination)
/// times one contact's, that the step keeps: the engine's sticking spring
/// stays bounded under Gear-5 up to ω δt = 0.56 and grows from 0.58
/// (`TangentialMode.AtTheSpringsCriticalStep…`); 0.45 leaves a fifth of it.
/// Verlet, not measured on the spring, gets the same.
inline constexpr double springs_stability_limit = 0.45;

/// The tangential and rolling springs' critical step for a contact side
/// whose one-contact ω² (`tangential_omega2`) is `omega2_per_s2`:
/// springs_stability_limit / √(springs_coordination ω²) = 0.184/ω [s].
[[nodiscard]] inline double springs_critical_step_s(double omega2_per_s2)
{
    return springs_stability_limit / std::sqrt(springs_coordination * omega2_per_s2);
}

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
/// 0.2 or less blew Gear-5 up at ω δt = 0.15). Nor the tangential and rolling
/// springs' critical step, their own ω δt = 0.3: a sticking spring has to
/// stay bounded, not be resolved (docs/model.md, "The tangential and rolling
/// springs in the step").
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
        /// Largest tangential mobility of a moving body, the sideways
        /// displacement of its contact point per unit force: 1/m + a²/I
        /// with the lever arm a bounded by r (1/m for a body that does not
        /// turn; a clump's sphere 1/M + (|b| + r)²/I_min) [1/kg]
        double max_tangential_mobility_per_kg = 0.0;
        /// Largest 1/I of a moving body that turns (a clump's sphere: its
        /// clump's 1/I_min): the rolling spring k_r = f_r K R*² turns it at
        /// k_r/I [1/(kg·m²)]
        double max_inverse_inertia_per_kg_m2 = 0.0;

        /// Folds in one body that does not turn (a node): its tangential mobility is 1/m.
        void include(double mass_kg, bool held, double radius_m, double plane_modulus_pa);
        /// Folds in one body that turns (a grain), with its tangential mobility and 1/I.
        void include(double mass_kg, bool held, double radius_m, double plane_modulus_pa,
            double tangential_mobility_per_kg, double inverse_inertia_per_kg_m2);
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
    /// k_t of the tangential spring F_t = −k_t F_n δ_t: its stiffness is
    /// K = k_t F_n, at the normal force of the reference overlap [1/m]
    double tangential_stiffness_per_m = 0.0;
    double friction_coeff = 0.0;                    ///< μ of body–body contacts (0: no tangential spring)
    std::vector<double> wall_friction_coeffs;       ///< μ of each wall's contacts, in wall order
    /// f_r of the rolling spring k_r = f_r K R*² while the rolling law is on; 0 when it is off
    double rolling_stiffness_factor = 0.0;
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
    /// Largest stable δt, damping included, of the normal contacts, the
    /// wire, the membrane and the tangential and rolling springs [s]
    double critical_s = 0.0;
    /// The same without damping and without the tangential and rolling
    /// springs: gear5_stability_limit over the highest ω of the normal
    /// contacts, the wire and the membrane, the oscillations `auto`
    /// resolves [s]
    double undamped_critical_s = 0.0;
    /// The tangential and rolling springs' own critical step,
    /// springs_critical_step_s of their highest one-contact ω² (undamped);
    /// infinity without a spring [s]
    double springs_critical_s = std::numeric_limits<double>::infinity();
    /// What `auto` uses: auto_time_step_fraction × undamped_critical_s, or
    /// critical_s where damping or the tangential and rolling springs bring
    /// that lower [s]
    double auto_s = 0.0;
    std::string limited_by;    ///< what sets critical_s, e.g. "wire segments", "grain–grain contacts"

    /// Whether damping brings the critical step below
    /// min_damped_step_fraction of the undamped one, springs included
    /// (overdamped_error): a step the springs set is no damping's doing.
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
/// bounded (Gershgorin) by ω² ≤ 12 k_m/m_m; and, undamped, the sticking
/// tangential and rolling springs of each contact at the normal force of
/// the reference overlap, not of an impact's (tangential_omega2 on the
/// more mobile side, with the kind's largest mobility: docs/model.md, "The
/// tangential and rolling springs in the step").
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

/// The stiffest live sticking spring, and the step it allows: what
/// stable_time_step says of a contact's tangential and rolling springs, at
/// the contact's own normal force instead of the one expected (docs/model.md,
/// "The tangential and rolling springs in the step"). Reported, not a stop:
/// a sticking spring beyond Gear-5's bound breaks at |δ_t| = μ/k_t and
/// slides with |F_t| ≤ μ F_n, so it chatters, bounded, where a normal
/// contact diverges.
struct LiveSpringLimit {
    /// springs_critical_step_s of the highest ω² of the sticking contacts'
    /// springs (undamped); infinity with none [s]
    double critical_s = std::numeric_limits<double>::infinity();
    double normal_force_n = 0.0;      ///< that contact's F_n [N]
    double stiffness_n_per_m = 0.0;   ///< its tangential spring K = k_t F_n [N/m]
    double omega2_per_s2 = 0.0;       ///< its ω² (tangential_omega2 of its more mobile side) [1/s²]
    std::string kinds;                ///< "grain–grain", "grain–wall", …
};

/// The stiffest live contact and the stiffest live sticking spring, from one pass.
struct LiveLimits {
    LiveContactLimit contact;
    LiveSpringLimit springs;
};

/// The stiffest live contact of `w` (LiveContactLimit) and, in the same
/// pass, its stiffest sticking spring (LiveSpringLimit): every touching
/// contact whose tangential spring sticks (μ > 0), with K = k_t F_n from
/// this step's |F_n|, on the more mobile of its moving sides (1/m + a²/I,
/// a = r − ξ/2; a clump's sphere bounded by 1/M + (|b| + a)²/I_min; a node
/// 1/m) and, while the rolling law is on, the rolling spring's f_r K R*²/I
/// on a grain side: as stable_time_step takes a contact's springs.
/// Threads and blocks as live_contact_limit. Without `with_springs` the
/// springs are not looked at (LiveLimits::springs stays without a limit):
/// a test whose springs have been reported once skips their share of the pass.
[[nodiscard]] LiveLimits live_limits(const World& w, ThreadPool& pool, bool with_springs = true);

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

/// How often a column test takes its stiffest live sticking springs
/// (LiveLimits::springs) in that pass [steps], a multiple of
/// live_check_steps: a spring beyond its limit is reported, not stopped on
/// (it chatters, bounded), so it needs no tighter watch, and their share of
/// the pass (two sides' mobilities per touching contact) was as much again as
/// the normal contacts' (perf of the study column's 80 kPa test, one thread:
/// 3.3 % of the samples in the pass with them every 10 steps, 1.7 % without).
inline constexpr std::uint64_t live_spring_check_steps = 100;
static_assert(live_spring_check_steps % live_check_steps == 0);

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

/// Words every live_spring_warning holds: how the reader of a checkpoint
/// written before the driver states kept `live_springs_reported`
/// (2026-12-07) finds whether its test has the warning (campaign/files.cpp).
inline constexpr const char* live_spring_warning_marker = "of the stiffest sticking tangential and rolling springs";
/// The warning of a column test whose step `dt_s` exceeds the live springs'
/// limit `springs` by more than live_contact_tolerance, `after` saying when:
/// the ratio, the contact and the fields to change
/// (contact.tangential_stiffness_per_m, engine.time_step_s). Recorded once
/// per test; the test goes on.
[[nodiscard]] std::string live_spring_warning(const LiveSpringLimit& springs, double dt_s, const std::string& after);

/// What to tell a run whose step `dt_s` exceeds the live limit `live` by more
/// than live_contact_tolerance, `after` saying when ("after 1200 steps of
/// the triaxial test"): the contact, its overlap against the reference, and
/// the fields to change.
[[nodiscard]] std::string live_contact_error(const LiveContactLimit& live, double dt_s, const std::string& after);

/// What to tell a run that blew up (a position became NaN or infinite) at
/// step `dt_s`, `after` saying when ("after 1200 steps of the preparation,
/// at t = 0.3 s"): that its step was too large for what it met, and the
/// field to change (engine.time_step_s) with a value to try, half the step.
/// Every driver's blow-up says this, so a user learns the same remedy from
/// each (the preparation, the box's compaction, the column tests).
[[nodiscard]] std::string blow_up_error(double dt_s, const std::string& after);

} // namespace wiredem::engine
