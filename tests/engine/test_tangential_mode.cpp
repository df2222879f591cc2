// The tangential and rolling springs' oscillation (engine/laws/
// tangential_mode.hpp, tangential_omega2) against a contact oscillating in
// stick in the engine: its period measured from the spring δ_t's zero
// crossings (docs/model.md, "The tangential and rolling springs are not in
// the step").
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "laws/tangential_mode.hpp"
#include "step.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

const Material grain_material{1e8, 0.3, 7800.0};
constexpr double r_a = 1.23e-3;
constexpr double g_m_per_s2 = 10.0;
const Material plate_material{1e9, 0.3, 7800.0};

/// Static Hertz overlap under the force F between E*, R* (undamped law).
double static_overlap_m(double force_n, double e_star_pa, double r_star_m)
{
    return std::pow(force_n / hertz_prefactor(e_star_pa, r_star_m), 2.0 / 3.0);
}

/// Steps `sim` for `steps` and returns the mean period of δ_t's x part
/// (contact `contact`), from its first to its last upward zero crossing,
/// linearly interpolated [s]; 0 with fewer than three crossings.
double measured_period_s(Simulation& sim, std::size_t contact, int steps)
{
    std::vector<double> ups;
    double prev = 0.0;
    int sliding = 0;
    for (int s = 0; s < steps; ++s) {
        sim.step();
        const TangentialState& t = sim.world.contacts.tangential[contact];
        sliding += t.sticking ? 0 : 1;
        const double x = t.spring_m.x();
        if (s > 0 && prev < 0.0 && x >= 0.0) ups.push_back((s + prev / (prev - x)) * sim.world.dt_s);
        prev = x;
    }
    EXPECT_EQ(sliding, 0); // in stick throughout: |δ_t| < μ/k_t
    if (ups.size() < 3) return 0.0;
    return (ups.back() - ups.front()) / static_cast<double>(ups.size() - 1);
}

/// One grain of radius r_a resting at its static overlap on a plate under
/// gravity (F_n = m g), k_t = 1e7 1/m (K = k_t m g: ω_t² = 3.5 k_t g, six
/// times the normal contact's ω², 1.5 g/ξ, here), rolling on at f_r = 1 or off,
/// moving at `velocity` and spinning at `spin`; δt at ω δt ≈ 0.02 of the
/// highest mode. Returns the lever arm a = r − ξ/2.
double grain_on_plate(Simulation& sim, bool rolling, const Vec3& velocity, const Vec3& spin)
{
    World& w = sim.world;
    reset_world(w, grain_material, 1e-6);
    w.gravity_m_per_s2 = Vec3(0.0, 0.0, -g_m_per_s2);
    w.contact.tangential.stiffness_per_m = 1e7;
    if (rolling) w.contact.rolling = RollingParams{1.0, 1.0, 0.0}; // μ_r = 1: never at its limit here
    add_wall(w, make_plate(0.0, +1.0, add_material(w, plate_material)));
    const double m = grain_material.density_kg_per_m3 * 4.0 / 3.0 * std::numbers::pi * r_a * r_a * r_a;
    const double e_star = effective_modulus_pa(grain_material.youngs_modulus_pa, grain_material.poisson_ratio,
        plate_material.youngs_modulus_pa, plate_material.poisson_ratio);
    const double overlap = static_overlap_m(m * g_m_per_s2, e_star, r_a);
    add_grain(w, Vec3(0.0, 0.0, r_a - overlap), r_a, 0, velocity, spin);
    begin_run(w, sim.pool());
    return r_a - 0.5 * overlap;
}

} // namespace

TEST(TangentialMode, AGrainOnAPlateOscillatesAtThreeAndAHalfKtFnOverM)
{
    // The contact point of a solid sphere moves sideways under a force F by
    // F (1/m + a²/I): the slip s = x − a φ obeys m_t s̈ = −K s with
    // 1/m_t = 1/m + a²/I (a = r − ξ/2; 3.5/m at a = r), K = k_t F_n. Started
    // sliding at v₀ without spin: the rolling part (s = 0) drifts, the slip
    // oscillates at that ω alone.
    Simulation sim(1);
    const double a = grain_on_plate(sim, false, Vec3(1e-4, 0.0, 0.0), Vec3::Zero());
    const World& w = sim.world;
    const double m = w.bodies[0].mass_kg[0];
    const double inertia = 1.0 / w.grain_rotation.inv_inertia_per_kg_m2[0];
    const double k = w.contact.tangential.stiffness_per_m * m * g_m_per_s2;
    const double omega2 = tangential_omega2(k, 1.0 / m + a * a / inertia, 0.0, 1.0 / inertia);
    EXPECT_NEAR(omega2 * m / k, 3.5, 1e-3); // a ≈ r
    const double period = measured_period_s(sim, 0, 4000);
    const double expected = 2.0 * std::numbers::pi / std::sqrt(omega2);
    // Gear-5 at ω δt ≈ 0.02 keeps the period to ~1e-6, the crossings'
    // interpolation over ten periods to better than 1e-5; the lever arm
    // (r or r − ξ/2: ξ/2r = 1e-4) bounds the tolerance.
    EXPECT_NEAR(period, expected, 2e-4 * expected);
}

TEST(TangentialMode, TwoEqualGrainsOscillateAtTwiceTheOneGrainsOmegaSquared)
{
    // Two equal grains stacked, the lower one on a frictionless plate
    // (μ_w = 0: no tangential force there), the upper pressing with its
    // weight; set sliding against each other at ±v₀. The slip s = Σ (x_i ∓
    // a φ_i) of one contact between two free spheres obeys
    // s̈ = −K s Σ (1/m_i + a_i²/I_i): ω² = 7 K/m for equal solid spheres
    // (a = r): tangential_omega2 of either body, summed.
    Simulation sim(1);
    World& w = sim.world;
    reset_world(w, grain_material, 1e-6);
    w.gravity_m_per_s2 = Vec3(0.0, 0.0, -g_m_per_s2);
    w.contact.tangential.stiffness_per_m = 1e7;
    Wall plate = make_plate(0.0, +1.0, add_material(w, plate_material));
    plate.friction_coeff = 0.0;
    add_wall(w, plate);
    const double m = grain_material.density_kg_per_m3 * 4.0 / 3.0 * std::numbers::pi * r_a * r_a * r_a;
    const double e_plate = effective_modulus_pa(grain_material.youngs_modulus_pa, grain_material.poisson_ratio,
        plate_material.youngs_modulus_pa, plate_material.poisson_ratio);
    const double e_grains = effective_modulus_pa(grain_material.youngs_modulus_pa, grain_material.poisson_ratio,
        grain_material.youngs_modulus_pa, grain_material.poisson_ratio);
    const double low_z = r_a - static_overlap_m(2.0 * m * g_m_per_s2, e_plate, r_a);
    const double overlap = static_overlap_m(m * g_m_per_s2, e_grains, 0.5 * r_a);
    add_grain(w, Vec3(0.0, 0.0, low_z), r_a, 0, Vec3(-1e-4, 0.0, 0.0));
    add_grain(w, Vec3(0.0, 0.0, low_z + 2.0 * r_a - overlap), r_a, 0, Vec3(1e-4, 0.0, 0.0));
    begin_run(w, sim.pool());
    std::size_t pair = w.contacts.size();
    for (std::size_t p = 0; p < w.contacts.size(); ++p)
        if (!is_wall(w.contacts.second[p]) && !is_wall(w.contacts.first[p])) pair = p;
    ASSERT_LT(pair, w.contacts.size());
    const double a = r_a - 0.5 * overlap;
    const double inertia = 1.0 / w.grain_rotation.inv_inertia_per_kg_m2[0];
    const double k = w.contact.tangential.stiffness_per_m * m * g_m_per_s2;
    const double omega2 = 2.0 * tangential_omega2(k, 1.0 / m + a * a / inertia, 0.0, 1.0 / inertia);
    EXPECT_NEAR(omega2 * m / k, 7.0, 2e-3);
    const double period = measured_period_s(sim, pair, 4000);
    const double expected = 2.0 * std::numbers::pi / std::sqrt(omega2);
    EXPECT_NEAR(period, expected, 2e-4 * expected);
}

TEST(TangentialMode, WithTheRollingSpringTheHighModeStaysUnderTheSumOfTheTwo)
{
    // The rolling spring k_r = f_r K R*² (R* = r on a plate) acts on the
    // rotation φ, the tangential one on s = x − a φ: with M = diag(m, I),
    // K = [[K, −K a], [−K a, K a² + k_r]] the modes solve det(K − ω² M) = 0,
    // 0.4 λ² − (1.4 + f_r) λ + f_r = 0 in ω² = λ K/m at a = r (λ = 5.55 at
    // f_r = 1). Started along the high mode's eigenvector, the slip
    // oscillates at that ω alone. tangential_omega2 adds the two springs'
    // ω²: K (1/m + a²/I) + k_r/I = 6 K/m, 8.1 % above it.
    // The grain's masses, as grain_on_plate makes it.
    Simulation probe(1);
    const double a = grain_on_plate(probe, true, Vec3::Zero(), Vec3::Zero());
    const double m = probe.world.bodies[0].mass_kg[0];
    const double inertia = 1.0 / probe.world.grain_rotation.inv_inertia_per_kg_m2[0];
    const double k = probe.world.contact.tangential.stiffness_per_m * m * g_m_per_s2;
    const double k_r = k * r_a * r_a;
    // The generalized eigenproblem of the 2×2: λ² m I − λ (K I + m (K a² + k_r)) + K k_r = 0.
    const double b = k * inertia + m * (k * a * a + k_r);
    const double omega2 = (b + std::sqrt(b * b - 4.0 * m * inertia * k * k_r)) / (2.0 * m * inertia);
    EXPECT_NEAR(omega2 * m / k, 5.5495, 2e-3);
    // Its eigenvector: (K − ω² m) u_x − K a u_φ = 0.
    const double u_phi = (k - omega2 * m) / (k * a);
    const double v0 = 3e-5; // a slip of 5.5 v₀/ω = 7 nm, under μ/k_t = 30 nm
    Simulation sim(1);
    grain_on_plate(sim, true, Vec3(v0, 0.0, 0.0), Vec3(0.0, v0 * u_phi, 0.0));
    const double period = measured_period_s(sim, 0, 4000);
    const double expected = 2.0 * std::numbers::pi / std::sqrt(omega2);
    EXPECT_NEAR(period, expected, 2e-4 * expected);
    // The bound: above the mode, by 8.1 %.
    const double bound = tangential_omega2(k, 1.0 / m + a * a / inertia, k_r, 1.0 / inertia);
    EXPECT_GT(bound, omega2);
    EXPECT_LT(bound, 1.09 * omega2); // 6/5.55
}
