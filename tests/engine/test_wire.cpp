// The wire against beam and bar theory.
#include "energy.hpp"
#include "contact/pair_kernel_simd.hpp"
#include "forces/wire_forces.hpp"
#include "forces/wire_simd.hpp"
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "laws/wire_bond.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>

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
    w.dt_s = stable_time_step(w).auto_s;
}

void hold(World& w, std::uint32_t node) { set_motion(w, {BodyKind::wire, node}, Motion::fixed); }

double area_m2() { return M_PI * paper_wire.radius_m * paper_wire.radius_m; }
double second_moment_m4() { return M_PI * std::pow(paper_wire.radius_m, 4) / 4.0; }

/// ζ, the angle between the segments x₁ − x₀ and x₂ − x₁ [rad].
double angle_of(const std::array<Vec3, 3>& p)
{
    const Vec3 a = p[1] - p[0], b = p[2] - p[1];
    return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// ∂f/∂x_node,d for every node and axis by central differences of step h [m].
template <class F>
std::array<Vec3, 3> central_differences(const std::array<Vec3, 3>& x, double h, F&& f)
{
    std::array<Vec3, 3> g;
    for (int node = 0; node < 3; ++node)
        for (int d = 0; d < 3; ++d) {
            auto plus = x, minus = x;
            plus[node][d] += h;
            minus[node][d] -= h;
            g[node][d] = (f(plus) - f(minus)) / (2 * h);
        }
    return g;
}

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
    const auto f = wire_bending_forces_n(x[0], x[1], x[2], k);
    const auto grad_e = central_differences(x, 1e-9, [&](const std::array<Vec3, 3>& p) {
        const double zeta = angle_of(p);
        return 0.5 * k * zeta * zeta;
    });
    for (int node = 0; node < 3; ++node)
        for (int d = 0; d < 3; ++d)
            EXPECT_NEAR(f[node][d], -grad_e[node][d], 1e-6 * f[0].norm()) << "node " << node << " axis " << d;
}

TEST(WireBending, AngleGradientIsTheDerivativeOfZetaAndIsZeroWhereTheDirectionIsUndefined)
{
    // ∇ζ drives the joint's damper (τ k_rot ζ̇ = τ k_rot ∇ζ · ẋ). Central
    // differences with h = 1e-9 m on ~1 mm segments: truncation h² |ζ'''|/6 ~
    // 1e-18 · 1e9 = 1e-9 /m and rounding ε ζ / h ~ 1e-7 /m, against |∇ζ| ~ 1e3 /m.
    std::array<Vec3, 3> x{Vec3(0, 0, 0), Vec3(1.2e-3, 0.1e-3, 0), Vec3(2.3e-3, 0.5e-3, 0.2e-3)};
    const double elastic = std::numeric_limits<double>::infinity();
    const auto g = wire_joint(x[0], x[1], x[2], 1e-5, 0.0, elastic).angle_gradient_per_m;
    const auto numeric = central_differences(x, 1e-9, angle_of);
    for (int node = 0; node < 3; ++node)
        for (int d = 0; d < 3; ++d)
            EXPECT_NEAR(g[node][d], numeric[node][d], 1e-6 * g[0].norm()) << "node " << node << " axis " << d;
    // ζ does not change when the joint moves or turns as a whole.
    EXPECT_LT((g[0] + g[1] + g[2]).norm(), 1e-12 * g[0].norm());
    EXPECT_LT((x[0].cross(g[0]) + x[1].cross(g[1]) + x[2].cross(g[2])).norm(), 1e-12 * g[0].norm() * 1e-3);

    // Straight, and a segment of zero length: no bending direction, no gradient.
    for (const auto& p : {std::array<Vec3, 3>{Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(2e-3, 0, 0)},
             std::array<Vec3, 3>{Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1e-3, 1e-3, 0)}})
        for (const Vec3& gi : wire_joint(p[0], p[1], p[2], 1e-5, 0.0, elastic).angle_gradient_per_m)
            EXPECT_EQ(gi, Vec3::Zero());
}

TEST(WireBending, BendAngleIsTheArctangentWithinAFewUlp)
{
    // bend_angle_rad is within 2.4 ulp of the exact arctangent (measured
    // against 50-digit arithmetic: scripts/fit_bend_angle.py) and glibc's
    // atan2 within 0.52 ulp, so the two differ by at most 2.9 ulp of ζ.
    const auto ulps_from_atan2 = [](double s, double c) {
        const double exact = std::atan2(s, c);
        const double ulp = std::nextafter(exact, 4.0) - exact;
        return std::abs(bend_angle_rad(s, c) - exact) / ulp;
    };
    double worst = 0.0;
    const auto at = [&](double zeta, double scale = 1.0) {
        worst = std::max(worst, ulps_from_atan2(scale * std::abs(std::sin(zeta)), scale * std::cos(zeta)));
    };
    const int n = 100000;
    for (int i = 0; i <= n; ++i) at(std::numbers::pi * i / n);                    // [0, π]
    for (int i = 0; i <= n; ++i) at(std::pow(10.0, -12.0 + 12.0 * i / n));       // nearly straight
    for (int i = 0; i <= n; ++i) at(std::numbers::pi - std::pow(10.0, -12.0 + 12.0 * i / n)); // nearly folded back
    // Where the reduction changes: tan ζ = tan(π/8), π/4, π/2, 3π/4.
    for (const double edge : {std::atan(bend_angle_tan_pi_8), std::numbers::pi / 4, std::numbers::pi / 2, 3 * std::numbers::pi / 4})
        for (int i = -1000; i <= 1000; ++i) at(edge + 1e-12 * i);
    for (int i = 1; i <= 1000; ++i) at(0.003 * i, std::pow(10.0, -3.0 + 6.0 * (i % 7) / 6.0)); // off the unit circle
    EXPECT_LE(worst, 2.9);
    // Exact where atan2 is, and NaN in, NaN out.
    EXPECT_EQ(bend_angle_rad(0.0, 1.0), 0.0);
    EXPECT_EQ(bend_angle_rad(0.0, -1.0), std::numbers::pi);
    EXPECT_EQ(bend_angle_rad(1.0, 0.0), std::numbers::pi / 2);
    EXPECT_EQ(bend_angle_rad(1.0, 1.0), std::numbers::pi / 4);
    EXPECT_EQ(bend_angle_rad(2.0, -2.0), std::atan2(2.0, -2.0));
    EXPECT_TRUE(std::isnan(bend_angle_rad(std::numeric_limits<double>::quiet_NaN(), 1.0)));
    EXPECT_TRUE(std::isnan(bend_angle_rad(0.5, std::numeric_limits<double>::quiet_NaN())));
}

TEST(WireBending, StraightChainFeelsNoBendingForce)
{
    const auto f = wire_bending_forces_n(Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(2e-3, 0, 0), 1e-5);
    for (const Vec3& v : f) EXPECT_EQ(v.norm(), 0.0);
}

// The elastic–perfectly-plastic joint (docs/model.md, "Wire"): ζ_y = ε_y l_w / r_w,
// 0.125 rad for the paper's wire at ε_y = 0.05.

namespace {

/// Three nodes with the angle ζ between the segments (in the x–y plane,
/// segment lengths `la`, `lb`) [m].
std::array<Vec3, 3> joint_at(double zeta, double la = 1.25e-3, double lb = 1.25e-3)
{
    return {Vec3(-la, 0, 0), Vec3(0, 0, 0), lb * Vec3(std::cos(zeta), std::sin(zeta), 0)};
}

const double yield_angle = wire_bending_yield_angle_rad(0.05, paper_wire.radius_m, paper_wire.segment_length_m);

} // namespace

TEST(WirePlasticJoint, YieldAngleIsYieldStrainTimesSegmentOverRadius)
{
    // M_y = σ_y π r³/4 over k_rot = E π r⁴/(4 l): ζ_y = (σ_y/E) l / r.
    EXPECT_DOUBLE_EQ(yield_angle, 0.05 * 1.25e-3 / 0.5e-3);
    EXPECT_EQ(paper_wire.bending_yield_strain, 0.05); // the default wire is plastic
    EXPECT_TRUE(std::isinf(wire_bending_yield_angle_rad(std::numeric_limits<double>::infinity(), 0.5e-3, 1.25e-3)));
}

TEST(WirePlasticJoint, BelowYieldIsElasticAndReturnsToItsRestAngle)
{
    // Bent to 0.9 ζ_y and back: ζ₀ stays 0, and the moment is k ζ as for the
    // straight-rest spring; at ζ = 0 again the joint feels nothing.
    const double k = 0.039;
    double rest = 0.0;
    for (double zeta : {0.3, 0.6, 0.9, 0.6, 0.3, 0.0}) {
        const auto p = joint_at(zeta * yield_angle);
        const WireJoint j = wire_joint(p[0], p[1], p[2], k, rest, yield_angle);
        const auto elastic = wire_bending_forces_n(p[0], p[1], p[2], k);
        for (int n = 0; n < 3; ++n) EXPECT_EQ(j.force_n[n], elastic[n]) << "at " << zeta << " ζ_y, node " << n;
        rest = j.rest_angle_rad;
        EXPECT_EQ(rest, 0.0);
    }
}

TEST(WirePlasticJoint, BentBeyondYieldKeepsTheMaximumAngleLessTheYieldAngle)
{
    // Loading to ζ_max: ζ₀ = ζ_max − ζ_y, the moment stays k ζ_y (perfectly
    // plastic). Unloading within 2 ζ_y is elastic (ζ₀ unchanged); bent back
    // further, it yields the other way, ζ₀ = ζ + ζ_y, never below 0.
    const double k = 0.039, zy = yield_angle;
    double rest = 0.0;
    auto bend_to = [&](double zeta) {
        const auto p = joint_at(zeta);
        const WireJoint j = wire_joint(p[0], p[1], p[2], k, rest, zy);
        rest = j.rest_angle_rad;
        return j;
    };
    for (double zeta = 0.0; zeta <= 1.5; zeta += 0.01) {
        const WireJoint j = bend_to(zeta);
        EXPECT_NEAR(rest, std::max(0.0, zeta - zy), 1e-12) << "loading, ζ = " << zeta;
        // The moment about node i is |F_{i+1}| |b| = k (ζ − ζ₀) ≤ k ζ_y.
        EXPECT_LE(j.force_n[2].norm() * 1.25e-3, k * zy * (1.0 + 1e-9));
    }
    const double formed = rest; // ζ_max − ζ_y, ζ_max the loop's last angle (≈ 1.5)
    EXPECT_NEAR(formed, 1.5 - zy, 0.011);
    for (double zeta : {formed + zy, formed, formed - 0.99 * zy}) {
        bend_to(zeta);
        EXPECT_EQ(rest, formed) << "unloading to " << zeta;
    }
    bend_to(formed - 1.5 * zy); // past the reverse yield
    EXPECT_NEAR(rest, formed - 0.5 * zy, 1e-12);
    bend_to(0.05); // straightened back: ζ₀ = ζ + ζ_y
    EXPECT_NEAR(rest, 0.05 + zy, 1e-12);
    EXPECT_EQ(yielded_rest_angle_rad(0.0, 0.01, zy), 0.01);      // within ζ_y of straight: kept
    EXPECT_EQ(yielded_rest_angle_rad(0.5, 0.0, std::numeric_limits<double>::infinity()), 0.0); // elastic wire
    EXPECT_GE(yielded_rest_angle_rad(0.0, 0.0, zy), 0.0);
}

TEST(WirePlasticJoint, ForcesAreMinusTheGradientOfHalfKZetaLessRestSquared)
{
    // Below the yield band (ζ₀ fixed) the forces are the exact −∇ of
    // ½ k (ζ − ζ₀)², on either side of ζ₀; they sum to zero and exert no torque.
    const double k = 2e-5;
    const std::array<Vec3, 3> x{Vec3(0, 0, 0), Vec3(1.2e-3, 0.1e-3, 0), Vec3(2.3e-3, 0.5e-3, 0.2e-3)};
    const double zeta = angle_of(x);
    for (double rest : {zeta - 0.1, zeta + 0.1, 1.5}) {
        const WireJoint j = wire_joint(x[0], x[1], x[2], k, rest, std::numeric_limits<double>::infinity());
        EXPECT_EQ(j.rest_angle_rad, rest);
        const auto& f = j.force_n;
        const auto grad_e = central_differences(x, 1e-9, [&](const std::array<Vec3, 3>& p) {
            const double d = angle_of(p) - rest;
            return 0.5 * k * d * d;
        });
        for (int node = 0; node < 3; ++node)
            for (int d = 0; d < 3; ++d)
                EXPECT_NEAR(f[node][d], -grad_e[node][d], 1e-6 * f[0].norm()) << "ζ₀ " << rest << " node " << node << " axis " << d;
        const Vec3 net = f[0] + f[1] + f[2];
        const Vec3 torque = x[0].cross(f[0]) + x[1].cross(f[1]) + x[2].cross(f[2]);
        EXPECT_LT(net.norm(), 1e-12 * f[0].norm());
        EXPECT_LT(torque.norm(), 1e-12 * f[0].norm() * 1e-3);
    }
}

TEST(WirePlasticJoint, ForceIsFiniteAndBoundedAtAStraightFormedJoint)
{
    // ζ₀ > 0 and ζ → 0: a cone point of ½ k (ζ − ζ₀)², where ∇ζ has no
    // direction. The force is k (ζ₀ − ζ)/|b| in magnitude above sin ζ = 10⁻⁶
    // and falls to zero below it: finite, bounded, zero when straight.
    const double k = 0.039, rest = 0.5, l = 1.25e-3;
    for (double zeta : {0.0, 1e-12, 1e-9, 1e-7, 1e-6, 1e-5, 1e-3, M_PI - 1e-9, M_PI}) {
        const auto p = joint_at(zeta);
        const WireJoint j = wire_joint(p[0], p[1], p[2], k, rest, std::numeric_limits<double>::infinity());
        for (const Vec3& f : j.force_n) ASSERT_TRUE(f.allFinite()) << "ζ = " << zeta;
        EXPECT_LE(j.force_n[2].norm(), k * std::abs(zeta - rest) / l * (1.0 + 1e-6)) << "ζ = " << zeta;
        EXPECT_LT((j.force_n[0] + j.force_n[1] + j.force_n[2]).norm(), 1e-9 * k / l) << "ζ = " << zeta;
        if (zeta >= 1e-5 && zeta < 1.0) {
            EXPECT_NEAR(j.force_n[2].norm(), k * (rest - zeta) / l, 1e-9 * k / l) << "ζ = " << zeta;
        }
    }
    const auto straight = joint_at(0.0);
    const WireJoint j = wire_joint(straight[0], straight[1], straight[2], k, rest, std::numeric_limits<double>::infinity());
    for (const Vec3& f : j.force_n) EXPECT_EQ(f.norm(), 0.0);
}

TEST(WirePlasticJoint, FormedArcKeepsItsShapeInFreeSpace)
{
    // Nine nodes on a circle of radius 2.5 mm (ζ = 2 asin(l_w/2R) = 0.505 rad
    // per joint, four ζ_y), no gravity, released. The first force evaluation
    // yields every joint to ζ₀ = ζ − ζ_y and leaves E₀ = ½ k ζ_y² per joint.
    // The arc springs back and comes to rest with every joint at its own rest
    // angle (no elastic energy left). Springback alone would leave ζ₀; the
    // free arc, released at once, also overshoots in its middle (a beam's
    // fourth-order relaxation has no maximum principle; measured: up to
    // 0.066 rad further), which yields some joints further. Yielding by Δζ₀
    // at the moment k ζ_y dissipates k ζ_y |Δζ₀|, and nothing but E₀ can pay
    // for it, so Σ |Δζ₀| ≤ n ζ_y / 2: the mean rest angle stays within ζ_y/2
    // of ζ − ζ_y, the arc keeps its curvature. With the specification's elastic
    // wire the same arc straightens.
    const double radius = 2.5e-3, l = paper_wire.segment_length_m;
    const double zeta = 2.0 * std::asin(l / (2.0 * radius));
    const int nodes = 9, joints = nodes - 2;
    auto released = [&](double yield_strain) {
        auto sim = std::make_unique<Simulation>(1);
        World& w = sim->world;
        w.gravity_m_per_s2 = Vec3::Zero();
        WireSpec spec = paper_wire;
        spec.bending_yield_strain = yield_strain;
        configure_wire(w, spec);
        for (int i = 0; i < nodes; ++i)
            append_wire_node(w, radius * Vec3(std::cos(i * zeta), std::sin(i * zeta), 0.0));
        w.dt_s = stable_time_step(w).auto_s;
        // Slowest bending mode of a free–free beam of length L: ω = 4.73² √(EI/(ρ A L⁴)).
        const double length = (nodes - 1) * l;
        const double omega = 4.73 * 4.73 * std::sqrt(paper_wire.youngs_modulus_pa * second_moment_m4()
                                                     / (paper_wire.density_kg_per_m3 * area_m2() * std::pow(length, 4)));
        relax(*sim, static_cast<std::uint64_t>(200.0 / (omega * w.dt_s)), 2.0 * omega * w.dt_s);
        return sim;
    };
    const auto plastic = released(0.05);
    const World& w = plastic->world;
    const auto& x = w.of(BodyKind::wire).x[0];
    double yielded_further = 0.0, mean_angle = 0.0;
    for (int i = 1; i + 1 < nodes; ++i) {
        const double rest = w.wire_rest_angle_rad[i], now = angle_of({x[i - 1], x[i], x[i + 1]});
        EXPECT_NEAR(now, rest, 1e-6 * zeta) << "joint " << i << " not at rest";
        EXPECT_GE(rest, zeta - yield_angle - 1e-12) << "joint " << i << " unbent beyond the springback";
        yielded_further += std::abs(rest - (zeta - yield_angle));
        mean_angle += now / joints;
    }
    EXPECT_LE(yielded_further, joints * yield_angle / 2.0);
    EXPECT_GE(mean_angle, zeta - yield_angle - 1e-12);
    EXPECT_LE(mean_angle, zeta - yield_angle / 2.0);
    EXPECT_LT(elastic_energy(w, plastic->pool()).wire_j, 1e-6 * joints * 0.5 * w.wire.bending_stiffness_n_m * yield_angle * yield_angle);

    const auto elastic = released(std::numeric_limits<double>::infinity());
    const auto& xe = elastic->world.of(BodyKind::wire).x[0];
    for (int i = 1; i + 1 < nodes; ++i) EXPECT_LT(angle_of({xe[i - 1], xe[i], xe[i + 1]}), 0.1 * zeta) << "joint " << i;
}

TEST(WireStretch, ExtensionUnderAxialLoadIsFLOverEA)
{
    Simulation sim(1);
    const int nodes = 21;
    straight_wire(sim, nodes);
    World& w = sim.world;
    hold(w, 0);
    const double force = 0.5; // N: strain 6e-4
    w.point_loads.set(BodyRef(BodyKind::wire, nodes - 1), Vec3(force, 0, 0));
    // Slowest axial mode of a fixed–free bar: ω = (π/2L)√(E/ρ).
    const double length = (nodes - 1) * paper_wire.segment_length_m;
    const double omega = M_PI / (2 * length) * std::sqrt(paper_wire.youngs_modulus_pa / paper_wire.density_kg_per_m3);
    relax(sim, static_cast<std::uint64_t>(40.0 / (omega * w.dt_s)), 2.0 * omega * w.dt_s);
    const double extension = w.of(BodyKind::wire).x[0][nodes - 1].x() - length;
    EXPECT_NEAR(extension / (force * length / (paper_wire.youngs_modulus_pa * area_m2())), 1.0, 0.01);
    for (double strain : w.wire_forces.segment_strain)
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
    w.point_loads.set(BodyRef(BodyKind::wire, nodes - 1), Vec3(0, 0, -force));
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
    w.dt_s = stable_time_step(w).auto_s;
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
    w.dt_s = stable_time_step(w).auto_s;
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
    w.dt_s = 0.02 * stable_time_step(w).auto_s; // fine steps: the rate, not the scheme
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
        const double e = w.wire_forces.segment_strain[0];
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
    const std::vector<Vec3> moving = w.wire_forces.node_force_n;
    for (std::uint32_t i = 0; i < x.size(); ++i) set_velocity(w, BodyRef(BodyKind::wire, i), Vec3::Zero());
    compute_wire_forces(w, sim.pool());
    const std::vector<Vec3> still = w.wire_forces.node_force_n;
    for (std::size_t i = 0; i < x.size(); ++i)
        EXPECT_LT((moving[i] - still[i]).norm(), 1e-9 * still[2].norm() + 1e-12) << "node " << i;
    const Vec3 v(0.0, 0.0, 2.0);
    set_velocity(w, BodyRef(BodyKind::wire, 2), v);
    compute_wire_forces(w, sim.pool());
    Vec3 net = Vec3::Zero();
    for (const Vec3& f : w.wire_forces.node_force_n) net += f;
    EXPECT_LT(net.norm(), 1e-9 * w.wire_forces.node_force_n[2].norm());
    EXPECT_LT((w.wire_forces.node_force_n[2] - still[2]).dot(v), 0.0);
}

// The SIMD segments and joints (forces/wire_simd.hpp, every instruction set
// the CPU has) give the scalar
// path's bits for every kind of joint: bent elastically, yielding, straight
// (sin ζ below 10⁻⁶ and below 10⁻⁹), folded back, after a segment of zero
// length, with and without the dashpots, in blocks that start anywhere.
TEST(WireSimd, SegmentsAndJointsGiveTheScalarBits)
{
    const std::vector<SimdKernels> choices = simd_choices();
    if (choices.empty()) GTEST_SKIP() << "neither AVX-512 nor AVX2 on this CPU: the scalar path is the only one";
    const RestoreSimdKernels restore;
    for (const double yield_strain : {0.05, std::numeric_limits<double>::infinity()}) {
        World w;
        WireSpec spec = paper_wire;
        spec.bending_yield_strain = yield_strain;
        configure_wire(w, spec);
        const double l = spec.segment_length_m;
        // 600 nodes (three blocks of compute_wire_forces and a rest): a
        // wobbly helix with every special joint somewhere in it.
        std::uint64_t state = 12345;
        auto uniform = [&] { // [−1, 1)
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            return static_cast<double>(state >> 11) * 0x1p-52 - 1.0;
        };
        auto uniform_zyx = [&] { // drawn z, y, x, one per statement (engine/scene.cpp says why)
            const double z = uniform(), y = uniform();
            return Vec3(uniform(), y, z);
        };
        Vec3 p = Vec3::Zero(), last_step = Vec3::Zero();
        for (int i = 0; i < 600; ++i) {
            const double phi = 0.09 * i;
            Vec3 step = l * Vec3(-std::sin(phi), std::cos(phi), 0.05) + 0.2 * l * uniform_zyx();
            if (i % 97 == 5) step = Vec3::Zero();                              // a segment of zero length
            if (i % 89 == 7 || i % 89 == 8) step = l * Vec3(0.0, 0.0, 1.0);    // straight: sin ζ = 0
            if (i % 83 == 11) step = l * Vec3(1e-10, 0.0, 1.0);                // sin ζ ≈ 1e-10
            if (i % 79 == 13) step = l * Vec3(3e-7, 0.0, 1.0);                 // 1e-9 < sin ζ < 1e-6
            if (i % 73 == 17) step = -last_step;                              // folded back: ζ = π
            p += step;
            last_step = step;
            append_wire_node(w, p, 0.3 * uniform_zyx());
        }
        for (std::size_t i = 0; i < w.wire_rest_angle_rad.size(); ++i) w.wire_rest_angle_rad[i] = 0.2 * (1.0 + uniform());
        for (const bool damped : {true, false}) {
            World run = w;
            if (damped) set_time_step(run, 1e-6);
            else run.wire.node_mass_kg = 0.0; // τ = 0: no dashpots
            ThreadPool pool(2);
            set_simd_kernels(SimdKernels::scalar);
            World scalar = run;
            compute_wire_forces(scalar, pool);
            const WireForces& a = scalar.wire_forces;
            const std::vector<double>& a_rest = scalar.wire_rest_angle_rad;
            for (const SimdKernels choice : choices) {
                set_simd_kernels(choice);
                World simd = run;
                compute_wire_forces(simd, pool);
                SCOPED_TRACE(testing::Message() << simd_wire_kernels().lanes << " lanes, damped " << damped);
                const WireForces& b = simd.wire_forces;
                const std::vector<double>& b_rest = simd.wire_rest_angle_rad;
                const auto bits_of = [](double v) { return std::bit_cast<std::uint64_t>(v); };
                ASSERT_EQ(a.segment_force_n.size(), b.segment_force_n.size());
                for (std::size_t s = 0; s < a.segment_force_n.size(); ++s) {
                    for (int c = 0; c < 3; ++c) EXPECT_EQ(bits_of(a.segment_force_n[s][c]), bits_of(b.segment_force_n[s][c])) << "segment " << s;
                    EXPECT_EQ(bits_of(a.segment_strain[s]), bits_of(b.segment_strain[s])) << "segment " << s;
                }
                for (std::size_t i = 0; i < a.node_force_n.size(); ++i) {
                    EXPECT_EQ(bits_of(a_rest[i]), bits_of(b_rest[i])) << "joint " << i;
                    for (int n = 0; n < 3; ++n)
                        for (int c = 0; c < 3; ++c)
                            EXPECT_EQ(bits_of(a.bending_force_n[n][i][c]), bits_of(b.bending_force_n[n][i][c])) << "joint " << i;
                    for (int c = 0; c < 3; ++c) EXPECT_EQ(bits_of(a.node_force_n[i][c]), bits_of(b.node_force_n[i][c])) << "node " << i;
                }
            }
            // The special joints were there: some yielded, some were straight.
            if (damped && std::isfinite(yield_strain)) {
                std::size_t yielded = 0;
                for (std::size_t i = 0; i < a_rest.size(); ++i) yielded += a_rest[i] != w.wire_rest_angle_rad[i];
                EXPECT_GT(yielded, 10u);
            }
        }
    }
}
