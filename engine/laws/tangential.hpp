// Tangential contact law (the model spec §3): a static spring whose stiffness
// scales with the normal force, F_t = −k_t F_n δ_t (k_t in 1/m, the paper's
// reading), that breaks into dynamic sliding when |F_t| > μ F_n or
// |δ_t| > d_cr. While sliding, F_t = −F_n min(μ, γ_t |v_t|) v̂_t: shear damping
// below the Coulomb bound, Coulomb friction above it. A sliding contact sticks
// again (a new spring, δ_t = 0) once the sliding has stopped: γ_t |v_t| ≤ μ
// (the relative sliding speed has dropped below μ/γ_t), or the slip velocity
// has turned back since the previous step (v_t · v_t,prev < 0), i.e. it went
// through zero within the step.
//
// Why the second test: an explicit step of Coulomb friction changes the slip
// velocity by Δv = μ F_n δt / m_t (1/m_t = Σ 1/m + r²/I, 3.5/m per solid
// sphere), and the window |v_t| ≤ μ/γ_t is 2μ/γ_t wide. Once
// Δv > 2μ/γ_t, i.e. γ_t F_n δt / m_t > 2 (the explicit stability number of
// the F_n-normalised shear dashpot c = γ_t F_n), the slip velocity can step
// over the window and the friction force flips every step: a limit cycle of
// slip speed ~Δv that never sticks. With masses × 100 and the auto δt this
// happens from F_n ≈ 0.2 N, i.e. under a few grains' weight: piles of ~300
// grains chattered with ~90 % of their contacts "sliding" and did not settle
// (docs/model.md, "Sliding contacts that chattered"). The reversal test
// catches the stop in the step in which it happens, whatever δt; it puts no
// bound on δt.
#pragma once

#include "core/types.hpp"

#include <cmath>

namespace wiredem::engine {

/// Memory of one tangential contact.
struct TangentialState {
    /// Sticking: δ_t, the spring's relative tangential displacement [m].
    /// Sliding: v_t δt of the last step [m], the slip direction that tells a
    /// reversal (zero when unknown: no reversal is detected).
    Vec3 spring_m = Vec3::Zero();
    bool sticking = true; ///< true: static spring; false: sliding
};

/// Parameters of the tangential law, shared by all contacts. The defaults
/// are the model's (and the job spec's "contact" object, api/job_spec.hpp,
/// ContactSpec, which holds these; its ranges: api/job_spec.cpp).
struct TangentialParams {
    double stiffness_per_m = 1e5;   ///< k_t in F_t = −k_t F_n δ_t [1/m]
    double friction_coeff = 0.3;    ///< μ, the Coulomb bound μ F_n
    double critical_slip_m = 1e-4;  ///< d_cr, the spring breaks beyond this slip [m]
    double damping_s_per_m = 1e3;   ///< γ_t [s/m]; F-normalised shear damping F_n min(μ, γ_t |v_t|)
    friend bool operator==(const TangentialParams&, const TangentialParams&) = default;
};

struct TangentialResult {
    Vec3 force_n;          ///< tangential force on the first body [N]
    TangentialState next;  ///< state to keep for the next step
};

/// Evaluates the tangential law for one step.
/// @param prev                state after the previous step
/// @param normal              unit normal of the contact (any orientation)
/// @param tangential_velocity_m_per_s  v_t, relative velocity of the first body's contact
///                            point with respect to the second's, in the tangent plane
/// @param normal_force_n      F_n ≥ 0 [N]
/// @param dt_s                time step [s]
[[nodiscard, gnu::always_inline]] inline TangentialResult tangential_force(const TangentialState& prev, const Vec3& normal,
    const Vec3& tangential_velocity_m_per_s, double normal_force_n, const TangentialParams& p,
    double dt_s) noexcept
{
    const Vec3& vt = tangential_velocity_m_per_s;
    const double coulomb_n = p.friction_coeff * normal_force_n;

    // Dynamic friction: F_t = −F_n min(μ, γ_t |v_t|) v̂_t.
    auto sliding = [&](double speed) -> TangentialResult {
        const double f = normal_force_n * std::fmin(p.friction_coeff, p.damping_s_per_m * speed);
        return {speed > 0.0 ? Vec3(-f / speed * vt) : Vec3(Vec3::Zero()), {vt * dt_s, false}};
    };
    Vec3 spring = Vec3::Zero();
    if (!prev.sticking) {
        const double speed = vt.norm();
        // Still sliding (here γ_t |v_t| > μ: Coulomb friction).
        if (p.damping_s_per_m * speed > p.friction_coeff && vt.dot(prev.spring_m) >= 0.0) return sliding(speed);
        // The sliding has stopped (γ_t |v_t| ≤ μ, or v_t turned back: it went
        // through zero within the step; see the top): a new spring from
        // δ_t = 0 takes this step's slip, under the same Coulomb and d_cr
        // bounds as any sticking step. (Without those bounds a contact whose
        // slip turned back at speed got k_t F_n |v_t| δt, several F_n at
        // 1 m/s: TriaxialTest.EndToEndRuns blew up.)
    } else {
        // Keep the spring in the current tangent plane as the contact turns:
        // drop its normal component and restore its length. (One square
        // root: the length ratio is √(|δ|²/|δ_⊥|²).)
        spring = prev.spring_m - prev.spring_m.dot(normal) * normal;
        const double new_len2 = spring.squaredNorm();
        if (new_len2 > 0.0) spring *= std::sqrt(prev.spring_m.squaredNorm() / new_len2);
    }
    spring += vt * dt_s;

    const Vec3 force = -p.stiffness_per_m * normal_force_n * spring;
    if (force.squaredNorm() > coulomb_n * coulomb_n || spring.squaredNorm() > p.critical_slip_m * p.critical_slip_m)
        return sliding(vt.norm()); // the spring breaks
    return {force, {spring, true}};
}

} // namespace wiredem::engine
