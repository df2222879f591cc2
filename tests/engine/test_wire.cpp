// The wire against beam and bar theory.
#include "energy.hpp"
#include "forces/wire_forces.hpp"
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "laws/wire_bond.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

const WireSpec paper_wire{}; // r_w = 0.5 mm, l_w = 1.25 mm, E_w = 1 GPa, ρ_w = 1000

/// A straight wire of `nodes` nodes along +x from the origin, no gravity.
void straight_wire(Simulation& sim, int nodes)
{
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    configure_wire(w, paper_wire);
    for (int i = 0; i < nodes; ++i) append_wire_node(w, Vec3(i * paper_wire.segment_length_m, 0, 0));
    w.dt_s = auto_time_step_fraction * critical_time_step(w).critical_s;
}

void hold(World& w, std::uint32_t node) { w.of(BodyKind::wire).inv_mass_per_kg[node] = 0.0; }

double area_m2() { return M_PI * paper_wire.radius_m * paper_wire.radius_m; }
double second_moment_m4() { return M_PI * std::pow(paper_wire.radius_m, 4) / 4.0; }

} // namespace

TEST(WireBending, CoupleHasZeroNetForceAndTorque)
{
    const Vec3 a(0.1e-3, 0.2e-3, -0.3e-3), b(1.3e-3, 0.1e-3, 0.2e-3), c(2.0e-3, 1.1e-3, 0.6e-3);
    const auto f = wire_bending_forces_n(a, b, c, 1e-5);
    const Vec3 net = f[0] + f[1] + f[2];
    const Vec3 torque = a.cross(f[0]) + b.cross(f[1]) + c.cross(f[2]);
    const double scale = f[0].norm();
    ASSERT_GT(scale, 0.0);
    EXPECT_LT(net.norm(), 1e-12 * scale);
    EXPECT_LT(torque.norm(), 1e-12 * scale * 1e-3);
}

TEST(WireBending, ForcesAreMinusTheGradientOfHalfKZetaSquared)
{
    const double k = 2e-5;
    std::array<Vec3, 3> x{Vec3(0, 0, 0), Vec3(1.2e-3, 0.1e-3, 0), Vec3(2.3e-3, 0.5e-3, 0.2e-3)};
    auto energy = [&](const std::array<Vec3, 3>& p) {
        const Vec3 a = p[1] - p[0], b = p[2] - p[1];
        const double zeta = std::atan2(a.cross(b).norm(), a.dot(b));
        return 0.5 * k * zeta * zeta;
    };
    const auto f = wire_bending_forces_n(x[0], x[1], x[2], k);
    const double h = 1e-9;
    for (int node = 0; node < 3; ++node)
        for (int d = 0; d < 3; ++d) {
            auto plus = x, minus = x;
            plus[node][d] += h;
            minus[node][d] -= h;
            const double numeric = -(energy(plus) - energy(minus)) / (2 * h);
            EXPECT_NEAR(f[node][d], numeric, 1e-6 * f[0].norm()) << "node " << node << " axis " << d;
        }
}

TEST(WireBending, StraightChainFeelsNoBendingForce)
{
    const auto f = wire_bending_forces_n(Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(2e-3, 0, 0), 1e-5);
    for (const Vec3& v : f) EXPECT_EQ(v.norm(), 0.0);
}

TEST(WireStretch, ExtensionUnderAxialLoadIsFLOverEA)
{
    Simulation sim(1);
    const int nodes = 21;
    straight_wire(sim, nodes);
    World& w = sim.world;
    hold(w, 0);
    const double force = 0.5; // N: strain 6e-4
    w.point_loads.push_back({{BodyKind::wire, nodes - 1}, Vec3(force, 0, 0)});
    // Slowest axial mode of a fixed–free bar: ω = (π/2L)√(E/ρ).
    const double length = (nodes - 1) * paper_wire.segment_length_m;
    const double omega = M_PI / (2 * length) * std::sqrt(paper_wire.youngs_modulus_pa / paper_wire.density_kg_per_m3);
    relax(sim, static_cast<std::uint64_t>(40.0 / (omega * w.dt_s)), 2.0 * omega * w.dt_s);
    const double extension = w.of(BodyKind::wire).x[0][nodes - 1].x() - length;
    EXPECT_NEAR(extension / (force * length / (paper_wire.youngs_modulus_pa * area_m2())), 1.0, 0.01);
    for (double strain : w.wire.segment_strain)
        EXPECT_NEAR(strain, force / (paper_wire.youngs_modulus_pa * area_m2()), 0.01 * strain);
}

TEST(WireCantilever, TipDeflectionMatchesEulerBernoulli)
{
    // Clamped by holding the first two nodes; a small tip load F along −z.
    Simulation sim(1);
    const int nodes = 22;
    straight_wire(sim, nodes);
    World& w = sim.world;
    hold(w, 0);
    hold(w, 1);
    const double ei = paper_wire.youngs_modulus_pa * second_moment_m4();
    // The bending spring at node 1 stands for the curvature over half a
    // segment on either side, so the beam starts half a segment before node 1.
    const double length = (nodes - 2 + 0.5) * paper_wire.segment_length_m;
    const double force = 1e-3 * 3 * ei / (length * length); // tip deflection ≈ 1e-3 L
    w.point_loads.push_back({{BodyKind::wire, nodes - 1}, Vec3(0, 0, -force)});
    // First cantilever mode: ω₁ = 1.875² √(EI/(ρ A L⁴)).
    const double omega = 1.875 * 1.875 * std::sqrt(ei / (paper_wire.density_kg_per_m3 * area_m2() * std::pow(length, 4)));
    relax(sim, static_cast<std::uint64_t>(40.0 / (omega * w.dt_s)), 2.0 * omega * w.dt_s);
    const double deflection = -w.of(BodyKind::wire).x[0][nodes - 1].z();
    EXPECT_NEAR(deflection / (force * std::pow(length, 3) / (3 * ei)), 1.0, 0.03);
}

TEST(WireDrop, StraightWireComesToRestFlatOnThePlateWithoutGainingEnergy)
{
    Simulation sim(2);
    World& w = sim.world;
    add_material(w, Material{1e9, 0.3, 7800.0});
    add_wall(w, make_plate(0.0, +1.0, 0));
    configure_wire(w, paper_wire);
    const int nodes = 40;
    const double drop = 0.2e-3;
    for (int i = 0; i < nodes; ++i) append_wire_node(w, Vec3(i * paper_wire.segment_length_m, 0, paper_wire.radius_m + drop));
    w.dt_s = auto_time_step_fraction * critical_time_step(w).critical_s;
    const double m = w.wire.node_mass_kg;
    const double e_star = effective_modulus_pa(1e9, 0.0, 1e9, 0.3);
    w.contact.normal_damping_s = hertz_damping_for_restitution_s(0.3, m, 0.05, e_star, paper_wire.radius_m);

    auto total_energy = [&] {
        return kinetic_energy_j(w, sim.pool()) + gravitational_energy_j(w) + elastic_energy(w, sim.pool()).total_j();
    };
    const double e0 = total_energy();
    const double fall = nodes * m * 10.0 * drop; // energy the fall releases
    double worst_gain = 0.0;
    for (int ms = 0; ms < 20; ++ms) {
        ASSERT_EQ(sim.run(static_cast<std::uint64_t>(1e-3 / w.dt_s)).end, RunEnd::completed);
        worst_gain = std::max(worst_gain, total_energy() - e0);
    }
    EXPECT_LT(worst_gain, 1e-3 * fall);
    EXPECT_LT(kinetic_energy_j(w, sim.pool()), 1e-3 * fall);
    // At rest each node sinks by its static Hertz overlap under its own weight.
    const double overlap = std::pow(3 * m * 10.0 / (4 * e_star * std::sqrt(paper_wire.radius_m)), 2.0 / 3.0);
    for (const Vec3& x : w.of(BodyKind::wire).x[0]) EXPECT_NEAR(x.z(), paper_wire.radius_m - overlap, 0.05 * overlap);
}

TEST(WireStability, AutomaticTimeStepLetsALoadedWireOnlyLoseEnergy)
{
    // A wire stretched by 0.1 % and bent into a zig-zag, released: the
    // energy never grows, and the wire's own damping (ξ_w of the highest
    // mode, which a zig-zag nearly is) takes almost all of it within 10⁵ steps.
    Simulation sim(1);
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    configure_wire(w, paper_wire);
    for (int i = 0; i < 30; ++i)
        append_wire_node(w, Vec3(i * 1.001 * paper_wire.segment_length_m, (i % 2) * 0.1e-3, 0));
    w.dt_s = auto_time_step_fraction * critical_time_step(w).critical_s;
    auto energy = [&] { return kinetic_energy_j(w, sim.pool()) + elastic_energy(w, sim.pool()).total_j(); };
    const double e0 = energy();
    double previous = e0;
    for (int block = 0; block < 100; ++block) {
        ASSERT_EQ(sim.run(1000).end, RunEnd::completed);
        EXPECT_LE(energy(), previous * (1.0 + 1e-9)) << "after " << (block + 1) * 1000 << " steps";
        previous = energy();
    }
    EXPECT_LT(energy(), 1e-2 * e0);
}

TEST(WireDamping, OneSegmentRingsDownAtTheKelvinVoigtRate)
{
    // Two free nodes, the segment stretched by 0.1 %: the relative motion is
    // a damped oscillator, μ = m/2, stiffness k_elo, dashpot τ k_elo, so its
    // damping ratio is ξ = ω₀ τ / 2 with ω₀ = √(2 k/m), i.e. ξ_w/√2
    // (τ = 2 ξ_w / √(4k/m)). The strain's successive maxima, one damped
    // period T_d = 2π/(ω₀ √(1 − ξ²)) apart, shrink by exp(−ξ ω₀ T_d).
    Simulation sim(1);
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    configure_wire(w, paper_wire);
    const double l0 = paper_wire.segment_length_m;
    append_wire_node(w, Vec3(0, 0, 0));
    append_wire_node(w, Vec3(1.001 * l0, 0, 0));
    w.dt_s = 0.02 * auto_time_step_fraction * critical_time_step(w).critical_s; // fine steps: the rate, not the scheme
    const double k = w.wire.axial_stiffness_n_per_m, m = w.wire.node_mass_kg;
    const double omega0 = std::sqrt(2.0 * k / m);
    const double xi = wire_damping_ratio / std::sqrt(2.0);
    EXPECT_NEAR(omega0 * wire_retardation_time_s(w.wire) / 2.0, xi, 1e-12);
    const double expected = std::exp(-xi * omega0 * 2.0 * M_PI / (omega0 * std::sqrt(1.0 - xi * xi)));
    // Track the strain's maxima.
    std::vector<double> maxima;
    double before = 0.0, now = 0.0;
    for (int i = 0; i < 400000 && maxima.size() < 3; ++i) {
        sim.step();
        const double e = w.wire.segment_strain[0];
        if (i >= 2 && now > before && now >= e && now > 0.0) maxima.push_back(now);
        before = now;
        now = e;
    }
    ASSERT_GE(maxima.size(), 2u);
    EXPECT_NEAR(maxima[1] / maxima[0], expected, 0.02 * expected);
}

TEST(WireDamping, RigidMotionOfABentWireFeelsOnlyTheSprings)
{
    // A bent, stretched five-node wire spinning and drifting as a rigid body:
    // neither dashpot sees a rate (Δl and ζ do not change), so the forces are
    // exactly the springs'. Then a node moving alone is slowed: its force
    // does negative work.
    Simulation sim(1);
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    configure_wire(w, paper_wire);
    const std::vector<Vec3> x{Vec3(0, 0, 0), Vec3(1.26e-3, 0.2e-3, 0), Vec3(2.4e-3, 0.7e-3, 0.1e-3),
        Vec3(3.5e-3, 1.4e-3, 0.3e-3), Vec3(4.4e-3, 2.3e-3, 0.2e-3)};
    for (const Vec3& p : x) append_wire_node(w, p);
    w.dt_s = 1e-8;
    const Vec3 spin(300.0, -200.0, 500.0), drift(0.3, -0.1, 0.2);
    for (std::uint32_t i = 0; i < x.size(); ++i) set_velocity(w, BodyRef(BodyKind::wire, i), drift + spin.cross(x[i]));
    compute_wire_forces(w, sim.pool());
    const std::vector<Vec3> moving = w.wire.node_force_n;
    for (std::uint32_t i = 0; i < x.size(); ++i) set_velocity(w, BodyRef(BodyKind::wire, i), Vec3::Zero());
    compute_wire_forces(w, sim.pool());
    const std::vector<Vec3> still = w.wire.node_force_n;
    for (std::size_t i = 0; i < x.size(); ++i)
        EXPECT_LT((moving[i] - still[i]).norm(), 1e-9 * still[2].norm() + 1e-12) << "node " << i;
    const Vec3 v(0.0, 0.0, 2.0);
    set_velocity(w, BodyRef(BodyKind::wire, 2), v);
    compute_wire_forces(w, sim.pool());
    Vec3 net = Vec3::Zero();
    for (const Vec3& f : w.wire.node_force_n) net += f;
    EXPECT_LT(net.norm(), 1e-9 * w.wire.node_force_n[2].norm());
    EXPECT_LT((w.wire.node_force_n[2] - still[2]).dot(v), 0.0);
}
