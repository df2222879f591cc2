// Rolling resistance (engine/laws/rolling.hpp), the analytical cases of Ai,
// Chen, Rotter & Ooi (2011): the law's torque is bounded by μ_r R* F_n and
// elastic below it; a ball rolling on a plate decelerates at (5/7) μ_r g and
// stops after 7 v₀²/(10 μ_r g); on an incline it holds below tan β = μ_r
// and rolls above with (5/7) g (sin β − μ_r cos β); energy is dissipated,
// never created; the torques between two grains are equal and opposite
// (angular momentum is conserved); results are the same on any thread count
// and continue bit-identically from a snapshot.
#include "energy.hpp"
#include "helpers.hpp"
#include "io/hdf5.hpp"
#include "io/snapshot.hpp"
#include "laws/rolling.hpp"
#include "state/state_hash.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

constexpr double radius_m = 1.23e-3;
constexpr double g_m_per_s2 = 10.0;

/// One grain (soft: E = 10⁸ Pa, for a large δt) resting at its static
/// overlap on a floor under gravity g along `down` (unit; tilted for an
/// incline: the floor stays z = 0), with rolling resistance μ_r and η_r.
/// No normal damping, μ = 0.3 (the ball rolls without slipping in every case
/// below: the friction needed, (2/7) of the driving force, is far below μ F_n).
void ball_on_floor(World& w, double mu_r, double eta_r, const Vec3& down)
{
    reset_world(w, Material{1e8, 0.3, 7800.0}, 1e-7);
    w.gravity_m_per_s2 = g_m_per_s2 * down;
    w.contact.rolling = RollingParams{mu_r, 1.0, eta_r};
    const std::uint8_t plate = add_material(w, Material{1e9, 0.3, 7800.0});
    add_wall(w, make_plate(0.0, +1.0, plate));
    add_grain(w, Vec3(0, 0, radius_m), radius_m, 0);
    set_time_step(w, stable_time_step(w).auto_s);
    // At rest at the static Hertz overlap under the normal part of the weight.
    const double weight_n = w.bodies[0].mass_kg[0] * g_m_per_s2 * -down.z();
    const double e_star = effective_modulus_pa(1e8, 0.3, 1e9, 0.3);
    const double overlap = std::pow(weight_n / ((4.0 / 3.0) * e_star * std::sqrt(radius_m)), 2.0 / 3.0);
    place_body(w, BodyRef(BodyKind::grain, 0), Vec3(0, 0, radius_m - overlap));
}

/// The limit angle of the spring, θ_lim = μ_r/(f_r k_t R*) [rad].
double limit_angle_rad(const World& w)
{
    return w.contact.rolling.friction_coeff
         / (w.contact.rolling.stiffness_factor * w.contact.tangential.stiffness_per_m * radius_m);
}

/// Translational and rotational kinetic energy, gravity's potential and the
/// Hertz contacts' elastic energy [J].
double mechanical_energy_j(Simulation& sim)
{
    const World& w = sim.world;
    const double m = w.bodies[0].mass_kg[0], inertia = 1.0 / w.grain_rotation.inv_inertia_per_kg_m2[0];
    const Vec3 v = velocity_m_per_s(w, BodyRef(BodyKind::grain, 0));
    const Vec3 omega = angular_velocity_rad_per_s(w, 0);
    return 0.5 * m * v.squaredNorm() + 0.5 * inertia * omega.squaredNorm() + gravitational_energy_j(w)
         + elastic_energy(w, sim.pool()).contacts_j;
}

} // namespace

TEST(RollingLaw, IsElasticBelowTheLimitAndBoundedByMuRRFnAtIt)
{
    const RollingParams p{0.1, 1.0, 0.0};
    const Vec3 n(0, 0, 1);
    const double fn = 2.0, r = 1e-3, k_t = 1e5, dt = 1e-6;
    const double k_r = k_t * fn * r * r, m_max = p.friction_coeff * r * fn;
    // A small rolling step: M = −k_r θ exactly.
    const Vec3 spin(0, 300.0, 0);
    const RollingResult small = rolling_torque(Vec3::Zero(), n, spin, fn, r, k_t, 1e-9, p, dt);
    EXPECT_NEAR((small.torque_n_m + k_r * spin * dt).norm(), 0.0, 1e-15 * m_max);
    EXPECT_LT(small.torque_n_m.norm(), m_max);
    // Rolling on in one direction, then another: never above M_max, and at
    // it once the spring has wound past θ_lim = μ_r/(k_t R*).
    RollingResult r_now{Vec3::Zero(), Vec3::Zero()};
    for (int s = 0; s < 4000; ++s) {
        const Vec3 w_rel = s < 2000 ? Vec3(0, 300.0, 40.0) : Vec3(-500.0, 0, 0);
        r_now = rolling_torque(r_now.next_rad, n, w_rel, fn, r, k_t, 1e-9, p, dt);
        ASSERT_LE(r_now.torque_n_m.norm(), m_max * (1.0 + 1e-14)) << "step " << s;
    }
    EXPECT_NEAR(r_now.torque_n_m.norm(), m_max, 1e-12 * m_max);
    EXPECT_NEAR(r_now.torque_n_m.normalized().x(), 1.0, 1e-9) << "it resists the last rolling, about −x";
    // With damping, the sum is bounded too.
    const RollingParams damped{0.1, 1.0, 0.3};
    // (θ stays below θ_lim = 1e-3 rad; the dashpot alone, 2 η_r √(I_r k_r) ω_r =
    // 0.013 N·m, is 67 times M_max.)
    const RollingResult d = rolling_torque(Vec3(0, 0.9 * p.friction_coeff / (k_t * r), 0), n, Vec3(0, 50.0, 0), fn, r, k_t,
        1e-6, damped, dt);
    ASSERT_LT(d.next_rad.norm(), p.friction_coeff / (k_t * r));
    EXPECT_LE(d.torque_n_m.norm(), m_max * (1.0 + 1e-14));
}

TEST(RollingLaw, TwistingAboutTheNormalIsFree)
{
    const RollingResult t = rolling_torque(Vec3::Zero(), Vec3(0, 0, 1), Vec3(0, 0, 500.0), 2.0, 1e-3, 1e5, 1e-9,
        RollingParams{0.1, 1.0, 0.3}, 1e-6);
    EXPECT_EQ(t.torque_n_m, Vec3::Zero());
    EXPECT_EQ(t.next_rad, Vec3::Zero());
}

TEST(RollingBall, OnAFlatPlateStopsWhereTheLawSays)
{
    // Rolling without slipping at v₀, the fully mobilised torque μ_r r m g
    // takes the energy ½ (m + I/r²) v² = (7/10) m v² at the rate μ_r r m g ω:
    // a = (5/7) μ_r g, stopping after s = 7 v₀²/(10 μ_r g) (Ai et al. 2011,
    // type C). The corrections are the spring's wind-up (θ_lim r = 0.8 µm,
    // 5e-4 s) and the lever arm r − ξ/2 (ξ/r = 2e-4); 0.5 % bounds them.
    const double mu_r = 0.1, v0 = 0.05;
    Simulation sim(1);
    World& w = sim.world;
    ball_on_floor(w, mu_r, 0.3, Vec3(0, 0, -1));
    set_velocity(w, BodyRef(BodyKind::grain, 0), Vec3(v0, 0, 0));
    w.grain_rotation.theta[1][0] = Vec3(0, v0 / radius_m, 0) * w.dt_s; // ω = v₀/r about +y: rolling along +x
    const double x0 = w.bodies[0].x[0][0].x();
    const double stop_s = v0 / (5.0 / 7.0 * mu_r * g_m_per_s2);
    const double expected = 7.0 * v0 * v0 / (10.0 * mu_r * g_m_per_s2);
    // Half-way through the stopping time it has gone 3/4 of the way (a
    // constant deceleration); at 1.5 times it, it stands where the law says.
    // (Positions, not speeds: the tangential spring, undamped while it
    // sticks, rings at ~1 mm/s, 0.1 µm.)
    const auto half = static_cast<std::uint64_t>(0.5 * stop_s / w.dt_s);
    ASSERT_EQ(sim.run(half).end, RunEnd::completed);
    const double t_half = static_cast<double>(half) * w.dt_s, a = v0 / stop_s;
    const double at_half = v0 * t_half - 0.5 * a * t_half * t_half;
    EXPECT_NEAR(w.bodies[0].x[0][0].x() - x0, at_half, 5e-3 * at_half);
    ASSERT_EQ(sim.run(2 * half).end, RunEnd::completed);
    EXPECT_NEAR(w.bodies[0].x[0][0].x() - x0, expected, 5e-3 * expected);

    // Without rolling resistance it rolls on at v₀.
    Simulation free(1);
    ball_on_floor(free.world, 0.0, 0.0, Vec3(0, 0, -1));
    set_velocity(free.world, BodyRef(BodyKind::grain, 0), Vec3(v0, 0, 0));
    free.world.grain_rotation.theta[1][0] = Vec3(0, v0 / radius_m, 0) * free.world.dt_s;
    ASSERT_EQ(free.run(half).end, RunEnd::completed);
    EXPECT_NEAR(free.world.bodies[0].x[0][0].x() - x0, v0 * static_cast<double>(half) * free.world.dt_s, 5e-3 * at_half);
}

TEST(RollingBall, OnAnInclineHoldsBelowTanBetaEqualsMuRAndRollsAbove)
{
    // Gravity's torque about the contact point, m g r sin β, against the
    // limit μ_r r m g cos β: the ball holds while tan β ≤ μ_r, its spring at
    // the angle of the statics, θ = m g r sin β / k_r = tan β/(k_t r) =
    // (tan β/μ_r) θ_lim; above, it rolls with a = (5/7) g (sin β − μ_r cos β).
    // The plane tilts from level to β over the first 0.02 s (gravity turns),
    // so that no dynamic overshoot winds the spring past its statics.
    const double mu_r = 0.1, ramp_s = 0.02;
    for (const double ratio : {0.6, 1.25}) {
        const double beta = std::atan(ratio * mu_r);
        auto down_at = [&](double tilt) { return Vec3(std::sin(tilt), 0.0, -std::cos(tilt)); };
        Simulation sim(1);
        World& w = sim.world;
        ball_on_floor(w, mu_r, 0.3, down_at(0.0));
        const std::uint64_t block = 100;
        const auto blocks = static_cast<int>(0.1 / (static_cast<double>(block) * w.dt_s));
        const int ramp_blocks = static_cast<int>(ramp_s / (static_cast<double>(block) * w.dt_s));
        // Positions at three equally spaced times from twice the ramp on.
        const int b1 = 2 * ramp_blocks, half = (blocks - b1) / 2, b2 = b1 + half, b3 = b1 + 2 * half;
        std::vector<std::pair<double, double>> samples; // (t, x)
        double turned = 0.0;                            // the largest angle the ball turned [rad]
        for (int b = 1; b <= blocks; ++b) {
            w.gravity_m_per_s2 = g_m_per_s2 * down_at(beta * std::min(1.0, static_cast<double>(b) / ramp_blocks));
            ASSERT_EQ(sim.run(block).end, RunEnd::completed);
            turned = std::max(turned, Eigen::AngleAxisd(w.grain_rotation.orientation[0]).angle());
            if (b == b1 || b == b2 || b == b3) samples.push_back({w.time_s, w.bodies[0].x[0][0].x()});
        }
        if (ratio < 1.0) {
            // Held: turned by less than θ_lim, its spring at the statics' angle.
            EXPECT_LT(turned, limit_angle_rad(w));
            const std::size_t p = w.contacts.find(BodyRef(BodyKind::grain, 0), wall_ref(0)).value();
            EXPECT_NEAR(w.contacts.rolling_rad[p].norm(), ratio * limit_angle_rad(w), 2e-2 * ratio * limit_angle_rad(w));
        } else {
            // The acceleration from the second difference of three positions
            // equally spaced in time (speeds ring with the tangential
            // spring, ~1 mm/s; positions by ~0.1 µm: 1e-3 of a here).
            ASSERT_EQ(samples.size(), 3u);
            const double h = samples[1].first - samples[0].first;
            ASSERT_NEAR(samples[2].first - samples[1].first, h, 1e-9 * h);
            const double a = 5.0 / 7.0 * g_m_per_s2 * (std::sin(beta) - mu_r * std::cos(beta));
            const double measured = (samples[2].second - 2.0 * samples[1].second + samples[0].second) / (h * h);
            EXPECT_NEAR(measured, a, 1e-2 * a);
        }
    }
}

TEST(RollingBall, DissipatesEnergyAndNeverCreatesIt)
{
    // The rolling ball of the flat-plate test, its mechanical energy sampled
    // every 100 steps: it never rises by more than the springs can hold
    // (½ M_max θ_lim for the rolling one, ½ μ F_n · μ/k_t for the
    // tangential one: together 3e-3 of the kinetic energy), and ends at
    // the energy of the ball at rest.
    const double mu_r = 0.1, v0 = 0.05;
    Simulation sim(1);
    World& w = sim.world;
    ball_on_floor(w, mu_r, 0.3, Vec3(0, 0, -1));
    set_velocity(w, BodyRef(BodyKind::grain, 0), Vec3(v0, 0, 0));
    w.grain_rotation.theta[1][0] = Vec3(0, v0 / radius_m, 0) * w.dt_s;
    const double m = w.bodies[0].mass_kg[0];
    const double kinetic = 0.7 * m * v0 * v0;
    const double springs = 0.5 * mu_r * radius_m * m * g_m_per_s2 * limit_angle_rad(w)
                         + 0.5 * w.contact.tangential.friction_coeff * m * g_m_per_s2
                               * (w.contact.tangential.friction_coeff / w.contact.tangential.stiffness_per_m);
    ASSERT_LT(springs, 1e-2 * kinetic);
    double previous = mechanical_energy_j(sim);
    const double start = previous;
    const auto blocks = static_cast<int>(1.5 * v0 / (5.0 / 7.0 * mu_r * g_m_per_s2) / w.dt_s / 100);
    for (int b = 0; b < blocks; ++b) {
        ASSERT_EQ(sim.run(100).end, RunEnd::completed);
        const double e = mechanical_energy_j(sim);
        ASSERT_LE(e, previous + springs) << "block " << b;
        previous = std::min(previous, e);
    }
    EXPECT_NEAR(start - mechanical_energy_j(sim), kinetic, 1e-2 * kinetic) << "the kinetic energy is gone";
}

TEST(RollingGrains, TorquesBetweenTwoGrainsAreEqualAndOppositeSoAngularMomentumIsKept)
{
    // Two grains meet head-on, one spinning about an axis in the tangent
    // plane: the rolling torque (with the tangential force) slows its spin
    // and turns the other, and the total angular momentum about the origin,
    // Σ (x × m v + I ω), stays what it was.
    Simulation sim(1);
    World& w = sim.world;
    double dt = 0.0;
    for (int pass = 0; pass < 2; ++pass) { // spins are stored as δt ω: δt first
        reset_world(w, Material{1e8, 0.3, 2600.0}, dt);
        w.contact.rolling = RollingParams{0.2, 1.0, 0.3};
        add_grain(w, Vec3(0, 0, 0), 1e-3, 0, Vec3(0.05, 0, 0), Vec3(0, 0, 2000.0));
        add_grain(w, Vec3(2.1e-3, 0.3e-3, 0), 1e-3, 0, Vec3(-0.05, 0, 0), Vec3(0, 500.0, 0));
        dt = stable_time_step(w).auto_s;
    }
    auto momentum = [&] {
        Vec3 l = Vec3::Zero();
        for (std::uint32_t i = 0; i < 2; ++i) {
            const double m = w.bodies[0].mass_kg[i];
            l += w.bodies[0].x[0][i].cross(m * velocity_m_per_s(w, BodyRef(BodyKind::grain, i)))
               + angular_velocity_rad_per_s(w, i) / w.grain_rotation.inv_inertia_per_kg_m2[i];
        }
        return l;
    };
    const Vec3 before = momentum();
    const Vec3 spin_before = angular_velocity_rad_per_s(w, 1);
    bool rolled = false;
    for (int s = 0; s < 4000; ++s) {
        sim.step();
        for (const Vec3& m : w.contacts.rolling_torque_n_m) rolled = rolled || m.norm() > 0.0;
    }
    EXPECT_TRUE(rolled) << "the rolling law acted";
    EXPECT_GT((angular_velocity_rad_per_s(w, 1) - spin_before).norm(), 1.0);
    EXPECT_NEAR((momentum() - before).norm(), 0.0, 1e-9 * before.norm());
}

namespace {

/// The kicked column of the determinism tests with rolling resistance, its
/// state hash every 250 steps.
std::vector<std::uint64_t> run_rolling_column(unsigned threads)
{
    Simulation sim(threads);
    build_kicked_column(sim.world, 7, 3, 1.0);
    sim.world.contact.rolling = RollingParams{0.1, 1.0, 0.3};
    std::vector<std::uint64_t> hashes;
    for (int block = 0; block < 6; ++block) {
        EXPECT_EQ(sim.run(250).end, RunEnd::completed);
        hashes.push_back(state_hash(sim.world));
    }
    std::size_t rolling = 0;
    for (const Vec3& m : sim.world.contacts.rolling_torque_n_m) rolling += m.norm() > 0.0;
    EXPECT_GT(rolling, 20u) << "contacts roll";
    return hashes;
}

} // namespace

TEST(RollingGrains, SameBitsOnOneAndSeveralThreadsAndWithOrWithoutTheSimdPaths)
{
    const std::vector<std::uint64_t> reference = run_rolling_column(1);
    EXPECT_EQ(run_rolling_column(3), reference);
    // The force kernels, the rolling law among them (the AVX2 wall lanes
    // have it too), run as every SIMD choice has them: the same bits.
    const RestoreSimdKernels restore;
    set_simd_kernels(SimdKernels::scalar);
    EXPECT_EQ(run_rolling_column(2), reference);
    // And the rolling springs are in the hash: without them the run differs.
    Simulation plain(1);
    build_kicked_column(plain.world, 7, 3, 1.0);
    ASSERT_EQ(plain.run(250).end, RunEnd::completed);
    EXPECT_NE(state_hash(plain.world), reference.front());
}

TEST(RollingGrains, ASnapshotContinuesBitIdentically)
{
    Simulation original(2);
    build_kicked_column(original.world, 7, 3, 1.0);
    original.world.contact.rolling = RollingParams{0.1, 0.5, 0.2};
    ASSERT_EQ(original.run(600).end, RunEnd::completed);
    std::size_t springs = 0;
    for (const Vec3& t : original.world.contacts.rolling_rad) springs += t.norm() > 0.0;
    ASSERT_GT(springs, 20u);
    const std::filesystem::path path
        = std::filesystem::temp_directory_path() / ("wiredem_test_rolling_" + std::to_string(::getpid()) + ".h5");
    const auto saved = save_snapshot(original.world, path);
    ASSERT_TRUE(saved.ok()) << saved.error();
    auto restored = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_TRUE(restored.ok()) << restored.error();
    Simulation resumed(3);
    resumed.world = std::move(restored).value();
    EXPECT_EQ(resumed.world.contact.rolling, original.world.contact.rolling);
    EXPECT_EQ(resumed.world.contacts.rolling_rad, original.world.contacts.rolling_rad);
    for (int block = 0; block < 4; ++block) {
        ASSERT_EQ(original.run(100).end, RunEnd::completed);
        ASSERT_EQ(resumed.run(100).end, RunEnd::completed);
        ASSERT_EQ(state_hash(resumed.world), state_hash(original.world)) << "after " << (block + 1) * 100 << " steps";
    }
}

TEST(RollingGrains, AVersionSixSnapshotHasNoRollingLaw)
{
    // Snapshots before version 7 have no rolling parameters: the law is off
    // in what they restore, whatever the file holds under those names.
    Simulation sim(1);
    build_kicked_column(sim.world, 7, 3, 1.0);
    ASSERT_EQ(sim.run(100).end, RunEnd::completed);
    World w = sim.world;
    w.contact.rolling = RollingParams{0.2, 1.0, 0.1};
    const std::filesystem::path path
        = std::filesystem::temp_directory_path() / ("wiredem_test_rolling_v6_" + std::to_string(::getpid()) + ".h5");
    ASSERT_TRUE(save_snapshot(w, path).ok());
    io::File::open_read_write(path).root().write_int_attribute("version", 6);
    auto r = restore_snapshot(path);
    std::filesystem::remove(path);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_FALSE(r.value().contact.rolling.on());
    EXPECT_EQ(state_hash(r.value()), state_hash(sim.world));
}
