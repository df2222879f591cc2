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

TEST(WireStability, AutomaticTimeStepKeepsALoadedWireFromGainingEnergy)
{
    // A wire stretched by 0.1 % and bent into a zig-zag, released without any
    // damping: 10⁵ steps must not add energy (Gear-5 drifts slowly downwards
    // or not at all at the automatic step).
    Simulation sim(1);
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    configure_wire(w, paper_wire);
    for (int i = 0; i < 30; ++i)
        append_wire_node(w, Vec3(i * 1.001 * paper_wire.segment_length_m, (i % 2) * 0.1e-3, 0));
    w.dt_s = auto_time_step_fraction * critical_time_step(w).critical_s;
    auto energy = [&] { return kinetic_energy_j(w, sim.pool()) + elastic_energy(w, sim.pool()).total_j(); };
    const double e0 = energy();
    ASSERT_EQ(sim.run(100000).end, RunEnd::completed);
    EXPECT_LT(energy(), 1.001 * e0);
    EXPECT_GT(energy(), 0.9 * e0);
}
