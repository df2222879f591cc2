#include "integrate/clumps.hpp"

#include "integrate/gear5.hpp"
#include "integrate/rotation.hpp"

#include <algorithm>
#include <cmath>

namespace wiredem::engine {
namespace {

/// The loads on clump i with its spheres' lever arms at orientation q, or,
/// given `arm_m` (indexed by grain id), those arms as worked out at q.
void sum_loads(World& w, std::uint32_t i, const Quat& q, const Vec3* arm_m = nullptr)
{
    const ClumpState& c = w.clumps;
    const std::vector<Vec3>& force = w.force_of(BodyKind::grain);
    Vec3 f = w.gravity_acts[static_cast<int>(BodyKind::grain)] ? Vec3(c.mass_kg[i] * w.gravity_m_per_s2) : Vec3::Zero();
    Vec3 tau = Vec3::Zero();
    const std::uint32_t end = c.first_member[i] + c.member_count[i];
    for (std::uint32_t m = c.first_member[i]; m < end; ++m) {
        f += force[m];
        const Vec3 arm = arm_m != nullptr ? arm_m[m] : Vec3(q * c.member_offset_m[m]);
        tau += arm.cross(force[m]) + w.grain_torque_n_m[m];
    }
    w.clump_loads.force_n[i] = f;
    w.clump_loads.torque_n_m[i] = tau;
}

/// x_k ← Σ_{j≥k} C(j,k) x_j for k ≥ first (Gear's predictor) of element i:
/// the in-place Taylor shift (pass p adds x_{j+1} to x_j for j ≥ p, from the
/// top down), skipping the derivatives below `first` (ω_b has no θ₀).
void predict_all(std::array<std::vector<Vec3>, gear_order>& x, std::size_t i, int first)
{
    for (int pass = 0; pass < gear_order - 1; ++pass)
        for (int j = gear_order - 2; j >= std::max(pass, first); --j) x[j][i] += x[j + 1][i];
}

/// Applies Δ = target − x₂ to every derivative with Gear-5's coefficients.
void correct_all(std::array<std::vector<Vec3>, gear_order>& x, std::size_t i, const Vec3& target, int first)
{
    const Vec3 delta = target - x[2][i];
    for (int k = first; k < gear_order; ++k) x[k][i] += gear5_corrector[k] * delta;
}

/// The Magnus term of a step, (δt³/12) ω × ω̇ = (w₁ × w₂)/6 in scaled derivatives.
Vec3 magnus(const Vec3& w1, const Vec3& w2)
{
    return w1.cross(w2) / 6.0;
}

/// I⁻¹ (w₁ × I w₁)/2: the gyroscopic part of δt²/2 ω̇_b, in scaled terms.
Vec3 half_gyroscopic(const Vec3& inertia, const Vec3& w1)
{
    return 0.5 * w1.cross(inertia.cwiseProduct(w1)).cwiseQuotient(inertia);
}

/// δt²/2 I⁻¹ τ_b.
Vec3 half_kick(const ClumpState& c, const ClumpLoads& loads, std::size_t i, const Quat& q, double half_dt2)
{
    return half_dt2 * (q.conjugate() * loads.torque_n_m[i]).cwiseQuotient(c.principal_inertia_kg_m2[i]);
}

/// The lever arms' scratch (ClumpLoads::member_arm_m), one per grain, for a
/// first half to fill and its second half to read.
Vec3* clump_arms(World& w)
{
    std::vector<Vec3>& arms = w.clump_loads.member_arm_m;
    arms.resize(w.of(BodyKind::grain).size());
    return arms.data();
}

bool finite(const ClumpState& c, std::size_t i)
{
    return c.x[0][i].allFinite() && c.x[1][i].allFinite() && c.omega[1][i].allFinite();
}

/// The free rotation of one step split along the principal axes (Verlet's
/// drift, the symmetric splitting z y x y z): each part turns q about a body
/// axis k by φ = fraction × ω_k δt and the body-frame angular momentum
/// L = I w₁ the opposite way. A turn about a body axis, (c, s e_k) with
/// c = cos(φ/2), s = sin(φ/2), has two zero components, so each part is
/// written out: q ⊗ (c, s e_k) is eight products, L turns by −φ in the plane
/// normal to e_k (cos φ = 1 − 2s², sin φ = 2cs) and keeps L_k. L is carried
/// across the five parts and made w₁ once, with 1/I; q is normalised once
/// after them (each part is a unit quaternion to rounding). Until
/// 2026-12-07 each part was a quaternion product, a normalisation, a
/// vector turn and three divisions (the same splitting; other roundings,
/// bench/README.md "Verlet's clump drift, rolling in lanes").
void free_rotation(Quat& q, Vec3& w1, const Vec3& inertia)
{
    constexpr int axis[5] = {2, 1, 0, 1, 2};
    constexpr double fraction[5] = {0.5, 0.5, 1.0, 0.5, 0.5};
    const Vec3 inv_inertia = inertia.cwiseInverse();
    Vec3 l = inertia.cwiseProduct(w1);
    double qw = q.w();
    Vec3 qv = q.vec();
    for (int part = 0; part < 5; ++part) {
        const int k = axis[part], i = (k + 1) % 3, j = (k + 2) % 3; // (i, j, k) right-handed
        const double phi = fraction[part] * (l[k] * inv_inertia[k]);
        const HalfAngle h = half_angle(phi * phi);
        const double c = h.cos_half, s = h.sin_half_over_angle * phi;
        // q ⊗ (c, s e_k): w = c q_w − s q_k, v = c q_v + s q_w e_k + s q_v × e_k.
        const double w = c * qw - s * qv[k];
        const double vi = c * qv[i] + s * qv[j], vj = c * qv[j] - s * qv[i], vk = c * qv[k] + s * qw;
        qw = w;
        qv[i] = vi, qv[j] = vj, qv[k] = vk;
        // L in the body frame turned by −φ about e_k.
        const double cos_phi = 1.0 - 2.0 * s * s, sin_phi = 2.0 * c * s;
        const double li = cos_phi * l[i] + sin_phi * l[j], lj = cos_phi * l[j] - sin_phi * l[i];
        l[i] = li, l[j] = lj;
    }
    q = Quat(qw, qv.x(), qv.y(), qv.z()).normalized();
    w1 = l.cwiseProduct(inv_inertia);
}

} // namespace

void gear5_predict_clumps(World& w, ThreadPool& pool)
{
    ClumpState& c = w.clumps;
    if (c.empty()) return;
    Vec3* arms = clump_arms(w);
    parallel_for(pool, c.size(), [&](std::size_t i) {
        const Vec3 w1 = c.omega[1][i], w2 = c.omega[2][i];
        const Vec3 turn = w1 + w2 + c.omega[3][i] + c.omega[4][i] + c.omega[5][i] + magnus(w1, w2);
        predict_all(c.x, i, 0);
        predict_all(c.omega, i, 1);
        const Quat q = (c.orientation[i] * rotation_quaternion(turn)).normalized();
        w.clump_loads.predicted_orientation[i] = q;
        place_clump_spheres(w, static_cast<std::uint32_t>(i), q, arms);
    });
}

bool gear5_correct_clumps(World& w, ThreadPool& pool)
{
    ClumpState& c = w.clumps;
    if (c.empty()) return true;
    const double half_dt2 = 0.5 * w.dt_s * w.dt_s;
    std::vector<char> ok(c.size(), 1);
    const Vec3* arms = w.clump_loads.member_arm_m.data(); // the predictor's, at the predicted orientation
    parallel_for(pool, c.size(), [&](std::size_t i) {
        const auto id = static_cast<std::uint32_t>(i);
        const Quat predicted = w.clump_loads.predicted_orientation[i];
        sum_loads(w, id, predicted, arms);
        correct_all(c.x, i, half_dt2 / c.mass_kg[i] * w.clump_loads.force_n[i], 0);
        // δt²/2 ω̇_b = δt²/2 I⁻¹ τ_b − ½ I⁻¹ (w₁ × I w₁), from the predicted w₁.
        const Vec3 target = half_kick(c, w.clump_loads, i, predicted, half_dt2)
                          - half_gyroscopic(c.principal_inertia_kg_m2[i], c.omega[1][i]);
        correct_all(c.omega, i, target, 1);
        const Vec3 w1 = c.omega[1][i], w2 = c.omega[2][i];
        const Vec3 turn = w1 - w2 + c.omega[3][i] - c.omega[4][i] + c.omega[5][i] + magnus(w1, w2);
        c.orientation[i] = (c.orientation[i] * rotation_quaternion(turn)).normalized();
        place_clump_spheres(w, id, c.orientation[i]);
        ok[i] = finite(c, i) ? 1 : 0;
    });
    for (char v : ok)
        if (v == 0) return false;
    return true;
}

void verlet_first_half_clumps(World& w, ThreadPool& pool)
{
    ClumpState& c = w.clumps;
    if (c.empty()) return;
    Vec3* arms = clump_arms(w);
    parallel_for(pool, c.size(), [&](std::size_t i) {
        c.x[0][i] += c.x[1][i] + c.x[2][i]; // the bodies' drift_flat, x₀ += x₁ + x₂
        c.x[1][i] += c.x[2][i];
        c.omega[1][i] += c.omega[2][i];     // L_b += δt/2 τ_b
        free_rotation(c.orientation[i], c.omega[1][i], c.principal_inertia_kg_m2[i]);
        place_clump_spheres(w, static_cast<std::uint32_t>(i), c.orientation[i], arms);
    });
}

bool verlet_second_half_clumps(World& w, ThreadPool& pool)
{
    ClumpState& c = w.clumps;
    if (c.empty()) return true;
    const double half_dt2 = 0.5 * w.dt_s * w.dt_s;
    std::vector<char> ok(c.size(), 1);
    const Vec3* arms = w.clump_loads.member_arm_m.data(); // the first half's, at the same orientation
    parallel_for(pool, c.size(), [&](std::size_t i) {
        const auto id = static_cast<std::uint32_t>(i);
        const Quat q = c.orientation[i];
        sum_loads(w, id, q, arms);
        c.x[2][i] = half_dt2 / c.mass_kg[i] * w.clump_loads.force_n[i];
        c.x[1][i] += c.x[2][i];
        c.omega[2][i] = half_kick(c, w.clump_loads, i, q, half_dt2);
        c.omega[1][i] += c.omega[2][i];
        place_clump_spheres_at_arms(w, id, q, arms);
        ok[i] = finite(c, i) ? 1 : 0;
    });
    for (char v : ok)
        if (v == 0) return false;
    return true;
}

void clump_initial_accelerations(World& w, ThreadPool& pool)
{
    ClumpState& c = w.clumps;
    if (c.empty()) return;
    const double half_dt2 = 0.5 * w.dt_s * w.dt_s;
    const bool gear = w.integrator == Integrator::gear5;
    parallel_for(pool, c.size(), [&](std::size_t i) {
        const Quat q = c.orientation[i];
        sum_loads(w, static_cast<std::uint32_t>(i), q);
        c.x[2][i] = half_dt2 / c.mass_kg[i] * w.clump_loads.force_n[i];
        c.omega[2][i] = half_kick(c, w.clump_loads, i, q, half_dt2);
        if (gear) c.omega[2][i] -= half_gyroscopic(c.principal_inertia_kg_m2[i], c.omega[1][i]);
    });
}

double clump_kinetic_energy_j(const State& s)
{
    const ClumpState& c = s.clumps;
    const double inv_dt2 = 1.0 / (s.dt_s * s.dt_s);
    double e = 0.0;
    for (std::size_t i = 0; i < c.size(); ++i) {
        const Vec3& w1 = c.omega[1][i];
        e += 0.5 * inv_dt2 * (c.mass_kg[i] * c.x[1][i].squaredNorm() + c.principal_inertia_kg_m2[i].dot(w1.cwiseProduct(w1)));
    }
    return e;
}

} // namespace wiredem::engine
