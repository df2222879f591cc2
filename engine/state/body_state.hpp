// Flat per-quantity arrays of the moving bodies. Index = body id within its
// kind; ids follow creation order and never change.
#pragma once

#include "core/types.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace wiredem::engine {

/// Number of Gear-5 scaled derivatives kept per degree of freedom (x₀ … x₅).
inline constexpr int gear_order = 6;

/// How a body moves. One stage of the integrator moves every body by its
/// motion type, so no driver moves bodies by hand or edits their masses.
enum class Motion : std::uint8_t {
    dynamic,   ///< integrated from its forces
    kinematic, ///< moves at its prescribed velocity x₁/δt (set_velocity) whatever the forces; they are still gathered (Caches::body_force_n)
    fixed,     ///< does not move
    /// A sphere of a clump (a grain of several rigid spheres: state/world.hpp,
    /// ClumpState): placed by its clump's motion every step; its contacts are
    /// those of a dynamic body, its forces are summed on the clump.
    clumped,
};

/// The spheres of one kind (grains, wire nodes or membrane nodes): what
/// defines each (radius, mass, motion, material: it travels with the body,
/// which is added between steps and keeps its id) beside what the step
/// advances (the Gear derivatives). All arrays have size() entries. The force
/// each step gathers on them is Caches::body_force_n.
struct TranslationalState {
    /// Gear-5 scaled derivatives: x[0] position [m], x[k] = δt^k/k! · d^k x/dt^k [m].
    std::array<std::vector<Vec3>, gear_order> x;
    std::vector<double> radius_m;          ///< contact radius [m]
    std::vector<double> mass_kg;           ///< [kg]
    std::vector<double> inv_mass_per_kg;   ///< 1/m [1/kg]
    std::vector<Motion> motion;            ///< dynamic (fixed when added without mass) unless set_motion says otherwise
    std::vector<std::uint8_t> material;    ///< index into Model::materials

    [[nodiscard]] std::size_t size() const { return radius_m.size(); }

    /// Appends one body at rest at `position_m` moving with `velocity_m_per_s`
    /// (scaled by δt into x[1]); returns its index. A body without mass is
    /// fixed (the rigid membrane's nodes, until set_membrane_rigid).
    std::uint32_t add(const Vec3& position_m, const Vec3& velocity_m_per_s, double radius_m_, double mass_kg_,
        std::uint8_t material_id, double dt_s)
    {
        x[0].push_back(position_m);
        x[1].push_back(velocity_m_per_s * dt_s);
        for (int k = 2; k < gear_order; ++k) x[k].push_back(Vec3::Zero());
        radius_m.push_back(radius_m_);
        mass_kg.push_back(mass_kg_);
        inv_mass_per_kg.push_back(mass_kg_ > 0.0 ? 1.0 / mass_kg_ : 0.0);
        motion.push_back(mass_kg_ > 0.0 ? Motion::dynamic : Motion::fixed); // nothing to integrate without a mass
        material.push_back(material_id);
        return static_cast<std::uint32_t>(size() - 1);
    }
};

/// Rotational state of the grains, parallel to their TranslationalState.
/// The rotation is integrated with the same Gear-5 scheme on a rotation
/// vector θ: theta[1] = δt ω, theta[2] = δt²/2 · dω/dt, …. theta[0] is not
/// integrated (neither integrator moves it; it keeps the value it was given,
/// zero): a sum of rotation vectors is no angle in 3D, and nothing reads it.
/// Until 2026-12-05 Gear-5 summed it. The orientation quaternion is the
/// grain's attitude, advanced from the corrected ω and renormalised every
/// step. The torque each step gathers is Caches::grain_torque_n_m.
struct RotationalState {
    std::array<std::vector<Vec3>, gear_order> theta;
    std::vector<Quat> orientation;            ///< unit quaternion
    std::vector<double> inv_inertia_per_kg_m2; ///< 1/I, 0 for a body that must not turn

    void add(double inertia_kg_m2)
    {
        for (auto& v : theta) v.push_back(Vec3::Zero());
        orientation.push_back(Quat::Identity());
        inv_inertia_per_kg_m2.push_back(inertia_kg_m2 > 0.0 ? 1.0 / inertia_kg_m2 : 0.0);
    }
};

} // namespace wiredem::engine
