// The tangential and rolling springs' oscillation (engine/laws/
// tangential_mode.hpp, tangential_omega2) against a contact oscillating in
// stick in the engine: its period measured from the spring δ_t's zero
// crossings; and the springs in the stable time step and in a column
// test's live check (docs/model.md, "The tangential and rolling springs in
// the step").
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "laws/tangential_mode.hpp"
#include "step.hpp"
#include "timestep.hpp"
#include "triaxial/loading.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
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

namespace {

/// ω² of the grain of grain_on_plate resting on the plate, by hand: its
/// springs at this step's F_n, K = k_t F_n, on the grain alone (the plate
/// does not move): K (1/m + a²/I), a = r − ξ/2, and with rolling at f_r = 1
/// the rolling spring's K R*²/I, R* = r against a plate.
double grain_on_plate_springs_omega2(const World& w, bool rolling)
{
    const ContactList& c = w.contacts;
    EXPECT_EQ(c.size(), 1u); // the grain–plate contact alone
    const double m = w.bodies[0].mass_kg[0];
    const double inv_inertia = w.grain_rotation.inv_inertia_per_kg_m2[0];
    const double arm = r_a - 0.5 * c.output[0].overlap_m;
    const double k = w.contact.tangential.stiffness_per_m * c.output[0].normal_force_n;
    return k * (1.0 / m + arm * arm * inv_inertia) + (rolling ? k * r_a * r_a * inv_inertia : 0.0);
}

/// What a column test's stepper needs of its driver's state.
struct StepperState {
    std::uint64_t steps = 0;
    double wall_time_s = 0.0;
    bool live_springs_reported = false;
    struct {
        std::vector<std::string> warnings;
    } result;
};

} // namespace

// The soft, heavily pressed contact of issue 42 item 4: with k_t = 1e7 1/m
// (the poured heap that blew up, docs/validation.md) the springs at the
// reference overlap's force are far stiffer than the normal contact
// (ω_t²/ω_n² ≈ 2.33 k_t ξ_ref, ~300 here), so they set the step, and
// `auto` is their critical step, not half the normal contacts' undamped
// one. By hand: at ξ = 0.02 R*, F_n = (4/3) E* √R* ξ^{3/2}, K = k_t F_n;
// on one grain (the step takes a contact's more mobile side alone, as the
// normal contact its lighter body), K (1/m + r²/I) (+ f_r K R*²/I
// rolling), R* = r/2 grain–grain and r grain–plate; δt = 0.45/(√6 ω) of the
// stiffer.
TEST(TangentialMode, WhereTheSpringsBindTheAutoStepIsTheirCriticalStep)
{
    for (const bool rolling : {false, true}) {
        SCOPED_TRACE(rolling ? "rolling" : "no rolling");
        Simulation sim(1);
        grain_on_plate(sim, rolling, Vec3::Zero(), Vec3::Zero());
        const World& w = sim.world;
        const double m = w.bodies[0].mass_kg[0];
        const double inv_inertia = w.grain_rotation.inv_inertia_per_kg_m2[0];
        const double k_t = w.contact.tangential.stiffness_per_m;
        const auto reference_force_n = [](double e_star, double r_star) {
            const double xi = reference_overlap_fraction * r_star;
            return 4.0 / 3.0 * e_star * std::sqrt(r_star) * xi * std::sqrt(xi);
        };
        const double e_pair = effective_modulus_pa(grain_material.youngs_modulus_pa, grain_material.poisson_ratio,
            grain_material.youngs_modulus_pa, grain_material.poisson_ratio);
        const double e_wall = effective_modulus_pa(grain_material.youngs_modulus_pa, grain_material.poisson_ratio,
            plate_material.youngs_modulus_pa, plate_material.poisson_ratio);
        const double mobility = 1.0 / m + r_a * r_a * inv_inertia;
        const double k_pair = k_t * reference_force_n(e_pair, 0.5 * r_a);
        const double k_wall = k_t * reference_force_n(e_wall, r_a);
        const double omega2_pair = k_pair * mobility + (rolling ? k_pair * 0.25 * r_a * r_a * inv_inertia : 0.0);
        const double omega2_wall = k_wall * mobility + (rolling ? k_wall * r_a * r_a * inv_inertia : 0.0);
        // As a packing's: six such contacts on the grain, ω δt = 0.45.
        const double expected = 0.45 / std::sqrt(6.0 * std::max(omega2_pair, omega2_wall));
        const StableStep st = stable_time_step(w);
        // The same operations but the order of a few products and the plane
        // moduli's divisions: a few ulps.
        EXPECT_NEAR(st.springs_critical_s, expected, 1e-12 * expected);
        EXPECT_EQ(st.critical_s, st.springs_critical_s);
        EXPECT_EQ(st.auto_s, st.critical_s);
        EXPECT_LT(st.auto_s, 0.1 * auto_time_step_fraction * st.undamped_critical_s); // the springs bind, by far
        EXPECT_FALSE(st.overdamped()); // a step the springs set is no damping's
        EXPECT_NE(st.limited_by.find("tangential and rolling springs"), std::string::npos) << st.limited_by;
    }
}

// The sticking spring under Gear-5, at the critical step the springs get
// (ω δt = 0.3) and beyond: a grain set sliding in stick on a plate keeps
// sticking for 20 000 steps with its slip not growing (it decays: the
// spring integrates the predicted slip velocity, a force Gear-5 damps);
// at ω δt = 0.6 the slip grows until the spring reaches μ/k_t and the
// contact slides. Measured between: it decays up to 0.56 and slides from
// 0.58 (0.3, 0.5, 0.52, 0.54, 0.56, 0.58, 0.6, 0.7), so the springs'
// bound is about 0.57 for this spring, not the harmonic oscillator's 0.35
// (docs/model.md, "The tangential and rolling springs in the step").
TEST(TangentialMode, AtTheSpringsCriticalStepTheSlipStaysBoundedAndBeyondItGrows)
{
    for (const double omega_dt : {0.3, 0.6}) {
        SCOPED_TRACE(omega_dt);
        Simulation sim(1);
        grain_on_plate(sim, false, Vec3(1e-4, 0.0, 0.0), Vec3::Zero());
        sim.step();
        const double omega = std::sqrt(grain_on_plate_springs_omega2(sim.world, false));
        set_time_step(sim.world, omega_dt / omega);
        double first = 0.0, last = 0.0;
        int sliding = 0;
        constexpr int steps = 20000;
        for (int s = 0; s < steps; ++s) {
            sim.step();
            const TangentialState& t = sim.world.contacts.tangential[0];
            sliding += t.sticking ? 0 : 1;
            if (s < 2000) first = std::max(first, t.spring_m.norm());
            if (s >= steps - 2000) last = std::max(last, t.spring_m.norm());
        }
        if (omega_dt == 0.3) {
            EXPECT_EQ(sliding, 0);
            EXPECT_LT(last, first); // not growing (a slip of ~5 nm against μ/k_t = 30 nm)
        } else {
            EXPECT_GT(sliding, 0); // grew to the friction limit
        }
    }
}

namespace {

/// A grain of radius r_a at the origin caged by its twelve nearest
/// neighbours of an FCC cell (held, each pressed to ξ = 0.02 R*, R* = r/2),
/// k_t = 1e7 1/m, no gravity, spinning about z at `spin_rad_per_s`.
/// Returns the index of the contact with the neighbour at (1, 1, 0)/√2.
std::size_t caged_grain(Simulation& sim, double spin_rad_per_s)
{
    World& w = sim.world;
    reset_world(w, grain_material, 1e-6);
    w.contact.tangential.stiffness_per_m = 1e7;
    add_grain(w, Vec3::Zero(), r_a, 0, Vec3::Zero(), Vec3(0.0, 0.0, spin_rad_per_s));
    const double d = 2.0 * r_a - reference_overlap_fraction * 0.5 * r_a;
    for (int i = 0; i < 3; ++i)
        for (const double s1 : {1.0, -1.0})
            for (const double s2 : {1.0, -1.0}) {
                Vec3 n = Vec3::Zero();
                n[i] = s1;
                n[(i + 1) % 3] = s2;
                const std::uint32_t k = add_grain(w, d / std::numbers::sqrt2 * n, r_a, 0, Vec3::Zero(), Vec3::Zero());
                set_motion(w, {BodyKind::grain, k}, Motion::fixed);
            }
    begin_run(w, sim.pool());
    sim.step();
    const ContactList& c = w.contacts;
    for (std::size_t p = 0; p < c.size(); ++p)
        if (c.touching[p] && std::min(c.first[p].index(), c.second[p].index()) == 0
            && std::max(c.first[p].index(), c.second[p].index()) == 1)
            return p;
    ADD_FAILURE() << "no contact with the first neighbour";
    return 0;
}

} // namespace

// The springs of a packing (springs_critical_step_s): a grain caged by
// twelve neighbours turns against all their springs at once. Turned by φ
// about z, each contact slips by a φ sin θ (θ its normal's angle to z:
// sin²θ = 1 for the four in the xy plane, 1/2 for the other eight), so the
// mode has ω² = K a² Σ sin²θ / I = 8 K a²/I = 20 K/m (a ≈ r): 5.71 times
// the one contact's K (1/m + a²/I) = 3.5 K/m that stable_time_step takes
// (by symmetry the turn and the shift do not couple). Measured: its period
// at ω δt = 0.02; at the old rule's step, 0.3 over one contact's ω, the
// mode is at ω δt = 0.3 √5.71 = 0.72, past the spring's bound (about
// 0.57), and the slip grows until the contacts slide; at the step the
// engine now gives (0.45 / √6 over one contact's ω: 0.44 for this mode)
// the slip stays in stick and does not grow.
TEST(TangentialMode, AGrainCagedByTwelveTurnsAgainstAllTheirSpringsAndTheStepKeepsItBounded)
{
    Simulation probe(1);
    const std::size_t p = caged_grain(probe, 0.0);
    const World& pw = probe.world;
    const double m = pw.bodies[0].mass_kg[0];
    const double inv_inertia = pw.grain_rotation.inv_inertia_per_kg_m2[0];
    const double k = pw.contact.tangential.stiffness_per_m * pw.contacts.output[p].normal_force_n;
    const double arm = r_a - 0.5 * pw.contacts.output[p].overlap_m;
    const double mode_omega2 = 8.0 * k * arm * arm * inv_inertia;
    const double one_contact_omega2 = tangential_omega2(k, 1.0 / m + arm * arm * inv_inertia, 0.0, inv_inertia);
    const double a2 = arm * arm / (r_a * r_a); // (1 − ξ/2r)² = 0.990: 5.698, not 20/3.5
    EXPECT_NEAR(mode_omega2 / one_contact_omega2, 20.0 * a2 / (1.0 + 2.5 * a2), 1e-12);
    // The slip a ω₀/ω = 4 nm, under μ/k_t = 30 nm.
    const double spin = 2.0;
    {
        Simulation sim(1);
        const std::size_t q = caged_grain(sim, spin);
        set_time_step(sim.world, 0.02 / std::sqrt(mode_omega2));
        const double period = measured_period_s(sim, q, 4000);
        const double expected = 2.0 * std::numbers::pi / std::sqrt(mode_omega2);
        EXPECT_NEAR(period, expected, 2e-4 * expected);
    }
    for (const bool old_rule : {true, false}) {
        SCOPED_TRACE(old_rule ? "0.3 / one contact's omega" : "springs_critical_step_s");
        Simulation sim(1);
        const std::size_t q = caged_grain(sim, spin);
        const double dt = old_rule ? 0.3 / std::sqrt(one_contact_omega2) : springs_critical_step_s(one_contact_omega2);
        set_time_step(sim.world, dt);
        double first = 0.0, last = 0.0;
        int sliding = 0;
        constexpr int steps = 20000;
        for (int s = 0; s < steps; ++s) {
            sim.step();
            const TangentialState& t = sim.world.contacts.tangential[q];
            sliding += t.sticking ? 0 : 1;
            if (s < 2000) first = std::max(first, t.spring_m.norm());
            if (s >= steps - 2000) last = std::max(last, t.spring_m.norm());
        }
        if (old_rule) {
            EXPECT_GT(sliding, 0); // grew to the friction limit
        } else {
            EXPECT_EQ(sliding, 0);
            EXPECT_LE(last, first);
        }
    }
}

// The live check of a column test reports the springs, and goes on: a
// grain resting on a plate, stepped by ColumnTestStepper at 0.9 and 1.1
// times live_contact_tolerance × its springs' live limit (by hand, from
// its F_n: K (1/m + a²/I)). Beyond it one warning naming the fields to
// change, once, also when a stepper continues the same test; within it none.
TEST(TangentialMode, AColumnTestReportsASpringBeyondItsLiveLimitOnceAndGoesOn)
{
    for (const double factor : {0.9, 1.1}) {
        SCOPED_TRACE(factor);
        Simulation sim(1);
        grain_on_plate(sim, false, Vec3::Zero(), Vec3::Zero());
        sim.step();
        const double limit = 0.45 / std::sqrt(6.0 * grain_on_plate_springs_omega2(sim.world, false));
        ThreadPool caller(1);
        EXPECT_NEAR(live_limits(sim.world, caller).springs.critical_s, limit, 1e-12 * limit);
        EXPECT_EQ(live_limits(sim.world, caller).springs.kinds, "grain–wall");
        set_time_step(sim.world, factor * live_contact_tolerance * limit);
        // The normal contact's own live limit is √6 times the springs' here
        // (ω_t² = 3.5 k_t F_n/m against 1.5 F_n/(ξ m)): far from a stop.
        ASSERT_GT(live_limits(sim.world, caller).contact.critical_s, 2.0 * limit);
        const RunControl control;
        const ColumnTestStepper<StepperState>::BetweenSteps none;
        StepperState st;
        for (int run = 0; run < 2; ++run) { // a second stepper: the test continued
            ColumnTestStepper<StepperState> stepper(sim, control, none, st, "the test", std::chrono::steady_clock::now());
            for (int s = 0; s < 2 * static_cast<int>(live_spring_check_steps); ++s)
                ASSERT_FALSE(stepper.step([] {}, [] { return std::pair<std::uint64_t, std::uint64_t>{0, 1}; }));
        }
        EXPECT_EQ(st.steps, 4 * live_spring_check_steps);
        if (factor < 1.0) {
            EXPECT_TRUE(st.result.warnings.empty());
        } else {
            ASSERT_EQ(st.result.warnings.size(), 1u);
            const std::string& warning = st.result.warnings[0];
            // At the first springs' check.
            const std::string first_check = "after " + std::to_string(live_spring_check_steps) + " steps of the test";
            EXPECT_EQ(warning.rfind(first_check, 0), 0u) << warning;
            EXPECT_NE(warning.find("contact.tangential_stiffness_per_m"), std::string::npos) << warning;
            EXPECT_NE(warning.find("engine.time_step_s"), std::string::npos) << warning;
        }
    }
}
