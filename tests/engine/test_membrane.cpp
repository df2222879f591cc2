// The membrane against thin-shell theory, and grains against the mesh.
#include "energy.hpp"
#include "forces/membrane_forces.hpp"
#include "forces/membrane_simd.hpp"
#include "forces/wire_forces.hpp"
#include "helpers.hpp"
#include "laws/hertz.hpp"
#include "laws/membrane_edge.hpp"
#include "timestep.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

using namespace wiredem::engine;
using namespace wiredem::engine::test;

namespace {

MembraneSpec small_membrane(double radius_m, double height_m)
{
    MembraneSpec m;
    m.radius_m = radius_m;
    m.height_m = height_m;
    return m;
}

/// Mean radial distance of the nodes of the middle row [m].
double mid_row_radius_m(const World& w)
{
    const MembraneMesh& m = w.membrane;
    const std::size_t row = m.rows / 2;
    double sum = 0.0;
    for (std::size_t c = 0; c < m.columns; ++c) {
        const Vec3& x = w.of(BodyKind::membrane).x[0][row * m.columns + c];
        sum += std::hypot(x.x(), x.y());
    }
    return sum / static_cast<double>(m.columns);
}

} // namespace

TEST(MembraneMesh, TrianglesAreNearlyEquilateralAndPointInwards)
{
    World w;
    build_membrane(w, small_membrane(20e-3, 30e-3));
    const MembraneMesh& m = w.membrane;
    const auto& x = w.of(BodyKind::membrane).x[0];
    EXPECT_EQ(m.triangles.size(), 2 * m.columns * (m.rows - 1));
    for (const auto& t : m.triangles) {
        const Vec3 n = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
        Vec3 out = (x[t[0]] + x[t[1]] + x[t[2]]) / 3.0;
        out.z() = 0;
        ASSERT_LT(n.dot(out), 0.0);
    }
    for (double l : m.edge_rest_m) {
        EXPECT_GT(l, 0.9 * 1.25e-3);
        EXPECT_LT(l, 1.1 * 1.25e-3);
    }
}

TEST(MembranePressure, RadialExpansionMatchesThinWalledCylinder)
{
    // σ₃ pushes along the inward normal (confinement); an internal pressure p
    // is σ₃ = −p. A triangular lattice of springs k = (√3/2) E d is an isotropic sheet with
    // Young's modulus E and Poisson ratio 1/3 (docs/model.md). With its rims
    // held, far from the rims the axial strain vanishes (σ_z = ν σ_θ), so
    //   Δr = (1 − ν²) p R² / (E d) = (8/9) p R² / (E d).
    Simulation sim(2);
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    const MembraneSpec spec = small_membrane(10e-3, 30e-3);
    build_membrane(w, spec);
    set_membrane_rigid(w, false);
    w.dt_s = stable_time_step(w).auto_s;
    const double r0 = mid_row_radius_m(w);
    const double p = 10e3;
    w.membrane.pressure_pa = -p;
    // Breathing mode ω = √(E/ρ(1−ν²))/R; relax over many of its periods.
    const double omega = std::sqrt(spec.youngs_modulus_pa / spec.density_kg_per_m3 / (8.0 / 9.0)) / spec.radius_m;
    relax(sim, static_cast<std::uint64_t>(60.0 / (omega * w.dt_s)), 2.0 * omega * w.dt_s);
    const double expected = 8.0 / 9.0 * p * spec.radius_m * spec.radius_m / (spec.youngs_modulus_pa * spec.thickness_m);
    EXPECT_NEAR((mid_row_radius_m(w) - r0) / expected, 1.0, 0.05);
}

namespace {

/// A pressurised membrane on a bed of held grains, one behind every free
/// node, placed so that the node must move `gap_m` inwards to touch it. At
/// rest, returns the share of the pressure on the middle row's nodes that
/// their grain contacts carry (Σ contact force / Σ pressure force, radial),
/// and the middle row's inward displacement [m].
struct BedResult {
    double contact_share = 0.0;
    double displacement_m = 0.0;
};
BedResult press_membrane_onto_a_bed_of_grains(MembraneEdgeLaw law, double pressure_pa, double gap_m)
{
    Simulation sim(2);
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    MembraneSpec spec = small_membrane(10e-3, 10e-3);
    spec.edges = law;
    build_membrane(w, spec);
    const MembraneMesh& m = w.membrane;
    const std::uint8_t grain_mat = add_material(w, Material{});
    const double rg = 0.4e-3;
    std::vector<std::uint32_t> grain_of_node(w.of(BodyKind::membrane).size());
    for (std::uint32_t i = 0; i < grain_of_node.size(); ++i) {
        if (m.node_fixed[i]) continue;
        const Vec3 x = w.of(BodyKind::membrane).x[0][i];
        const Vec3 inward = -Vec3(x.x(), x.y(), 0.0).normalized();
        grain_of_node[i] = static_cast<std::uint32_t>(w.of(BodyKind::grain).size());
        add_grain(w, x + inward * (gap_m + spec.contact_radius_m + rg), rg, grain_mat);
        set_motion(w, {BodyKind::grain, grain_of_node[i]}, Motion::fixed); // held
    }
    set_membrane_rigid(w, false);
    w.dt_s = stable_time_step(w).auto_s;
    const double r0 = mid_row_radius_m(w);
    w.membrane.pressure_pa = pressure_pa;
    const double omega = std::sqrt(spec.youngs_modulus_pa / spec.density_kg_per_m3) / spec.radius_m;
    relax(sim, static_cast<std::uint64_t>(60.0 / (omega * w.dt_s)), 2.0 * omega * w.dt_s);

    // Radial balance of the middle row: pressure in, contacts out.
    const std::size_t row = m.rows / 2;
    const auto& x = w.of(BodyKind::membrane).x[0];
    double pressure_n = 0.0, contact_n = 0.0;
    for (std::size_t c = 0; c < m.columns; ++c) {
        const std::size_t i = row * m.columns + c;
        const Vec3 out = Vec3(x[i].x(), x[i].y(), 0.0).normalized();
        for (const auto& t : m.triangles) // σ₃ A n_in / 3 of each triangle with a corner at the node
            if (t[0] == i || t[1] == i || t[2] == i)
                pressure_n -= (m.pressure_pa / 6.0 * (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]])).dot(out);
        contact_n -= w.force_of(BodyKind::grain)[grain_of_node[i]].dot(out); // reaction on the node
    }
    return {contact_n / pressure_n, r0 - mid_row_radius_m(w)};
}

} // namespace

TEST(MembranePressure, SlackMembraneHandsTheWholePressureToTheGrains)
{
    // The membrane must contract by the gap (and the Hertz overlap) to reach
    // the grains. Linear edges would then hold up (9/8) E d u / R² of σ₃ by
    // hoop compression (the test below); the gap is chosen so that this is
    // about half. A wrinkling, tension-only sheet carries none of it: the
    // grains take the whole pressure (to the relaxation's residue, ≪ 1 %).
    const double p = 20e3, e_d = 1e8 * 1e-3, radius = 10e-3;
    const double gap = 0.5 * p * radius * radius / (9.0 / 8.0 * e_d);
    const BedResult r = press_membrane_onto_a_bed_of_grains(MembraneEdgeLaw::tension_only, p, gap);
    EXPECT_GT(r.displacement_m, gap);
    EXPECT_NEAR(r.contact_share, 1.0, 0.01);
}

TEST(MembranePressure, LinearMembraneHoldsUpPartOfThePressureByHoopCompression)
{
    // Thin-shell theory for the lattice (E, ν = 1/3, docs/model.md) with the
    // rims held (ε_z = 0): a uniform inward displacement u carries
    // p_hoop = E d u / ((1 − ν²) R²); the grains get the rest, 1 − p_hoop/σ₃.
    const double p = 20e3, e_d = 1e8 * 1e-3, radius = 10e-3;
    const double gap = 0.5 * p * radius * radius / (9.0 / 8.0 * e_d);
    const BedResult r = press_membrane_onto_a_bed_of_grains(MembraneEdgeLaw::linear, p, gap);
    const double hoop_share = 9.0 / 8.0 * e_d * r.displacement_m / (radius * radius) / p;
    EXPECT_GT(hoop_share, 0.4);
    EXPECT_NEAR(r.contact_share, 1.0 - hoop_share, 0.05);
}

TEST(MembraneContact, GrainPressedAgainstRigidMembraneGetsTheHertzForce)
{
    Simulation sim(1);
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    const std::uint8_t grain_mat = add_material(w, Material{});
    const MembraneSpec spec = small_membrane(20e-3, 20e-3);
    build_membrane(w, spec);
    const MembraneMesh& m = w.membrane;
    const std::uint32_t node = static_cast<std::uint32_t>(m.rows / 2 * m.columns);
    const Vec3 xn = w.of(BodyKind::membrane).x[0][node];
    const Vec3 inward = -Vec3(xn.x(), xn.y(), 0).normalized();
    const double rp = 1.23e-3, overlap = 1e-5;
    add_grain(w, xn + inward * (rp + spec.contact_radius_m - overlap), rp, grain_mat);
    w.dt_s = 1e-8;
    sim.step();
    const double e_star = effective_modulus_pa(10e9, 0.3, spec.youngs_modulus_pa, spec.poisson_ratio);
    const double expected = 4.0 / 3.0 * e_star * std::sqrt(effective_radius_m(rp, spec.contact_radius_m)) * std::pow(overlap, 1.5);
    const MembraneLoad load = membrane_contact_load(w, sim.pool());
    EXPECT_EQ(load.contacts, 1u);
    EXPECT_EQ(load.nodes_in_contact, 1u);
    EXPECT_NEAR(load.normal_force_n / expected, 1.0, 1e-6);
    EXPECT_NEAR(load.radial_force_n / expected, 1.0, 1e-6);
    // The grain is pushed inwards; the rigid node does not move.
    EXPECT_NEAR(w.force_of(BodyKind::grain)[0].dot(inward) / expected, 1.0, 1e-6);
    EXPECT_EQ((w.of(BodyKind::membrane).x[0][node] - xn).norm(), 0.0);
}

TEST(MembraneContact, WireNodePressingOnTheMembraneCountsInItsLoad)
{
    // The specimen is grains and wire; σ₃,eff must see the membrane's
    // contacts with both.
    Simulation sim(1);
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    build_membrane(w, small_membrane(20e-3, 20e-3));
    const MembraneMesh& m = w.membrane;
    const Vec3 xn = w.of(BodyKind::membrane).x[0][m.rows / 2 * m.columns];
    const Vec3 inward = -Vec3(xn.x(), xn.y(), 0).normalized();
    const WireSpec wire{};
    configure_wire(w, wire);
    append_wire_node(w, xn + inward * (wire.radius_m + MembraneSpec{}.contact_radius_m - 1e-5), Vec3::Zero());
    w.dt_s = 1e-8;
    sim.step();
    ASSERT_EQ(w.contacts.size(), 1u);
    ASSERT_GT(w.contacts.output[0].normal_force_n, 0.0);
    const MembraneLoad load = membrane_contact_load(w, sim.pool());
    EXPECT_EQ(load.contacts, 1u);
    EXPECT_EQ(load.normal_force_n, w.contacts.output[0].normal_force_n);
}

namespace {

/// Shoots one body of `kind` (added by `add_body(w, start, velocity)`) at 2 m/s
/// from 3 mm inside at the widest hole of a rigid mesh, the centroid of a
/// mid-height triangle, for 20 000 steps, and checks that its centre never
/// reaches the mesh and that it bounces back.
template <class AddBody>
void expect_bounces_off_the_mesh(BodyKind kind, AddBody add_body)
{
    Simulation sim(1);
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    build_membrane(w, small_membrane(10e-3, 15e-3));
    const MembraneMesh& m = w.membrane;
    const auto& t = m.triangles[m.triangles.size() / 2];
    const auto& x = w.of(BodyKind::membrane).x[0];
    const Vec3 centroid = (x[t[0]] + x[t[1]] + x[t[2]]) / 3.0;
    const Vec3 outward = Vec3(centroid.x(), centroid.y(), 0).normalized();
    add_body(w, centroid - outward * 3e-3, 2.0 * outward);
    w.dt_s = stable_time_step(w).auto_s;
    double max_reach = 0.0;
    for (int s = 0; s < 20000; ++s) {
        sim.step();
        max_reach = std::max(max_reach, w.of(kind).x[0][0].dot(outward));
    }
    EXPECT_LT(max_reach, centroid.dot(outward)); // its centre never reached the mesh
    EXPECT_LT(velocity_m_per_s(w, {kind, 0}).dot(outward), 0.0); // bounced back
}

} // namespace

TEST(MembraneContact, GrainCannotPassThroughTheMesh)
{
    expect_bounces_off_the_mesh(BodyKind::grain, [](World& w, const Vec3& at, const Vec3& v) {
        add_grain(w, at, 1.23e-3, add_material(w, Material{}), v);
    });
}

TEST(MembraneContact, WireNodeCannotPassThroughTheMesh)
{
    // Wire–membrane contact is modelled (docs/model.md): a wire node (r_w =
    // 0.5 mm) aimed at a triangle's centroid, l_m/√3 ≈ 0.72 mm from its three
    // node spheres (r_m = 0.5 mm), bounces off.
    expect_bounces_off_the_mesh(BodyKind::wire, [](World& w, const Vec3& at, const Vec3& v) {
        configure_wire(w, WireSpec{});
        append_wire_node(w, at, v);
    });
}

TEST(MembraneStability, AutomaticTimeStepKeepsAPressurisedMembraneFromGainingEnergy)
{
    // Pressure switched on suddenly, no damping: the membrane oscillates about
    // its squeezed state. The confining pressure is a conservative load on a
    // membrane with held rims (work −σ₃ ΔV), so E = kinetic + elastic + σ₃ (V − V₀)
    // must not grow.
    Simulation sim(2);
    World& w = sim.world;
    w.gravity_m_per_s2 = Vec3::Zero();
    // Linear edges: a tension-only sheet with nothing inside would collapse.
    MembraneSpec spec = small_membrane(5e-3, 8e-3);
    spec.edges = MembraneEdgeLaw::linear;
    build_membrane(w, spec);
    set_membrane_rigid(w, false);
    w.dt_s = stable_time_step(w).auto_s;
    const double p = 20e3;
    w.membrane.pressure_pa = p;
    const double v0 = membrane_volume_m3(w);
    auto energy = [&] {
        return kinetic_energy_j(w, sim.pool()) + elastic_energy(w, sim.pool()).total_j() + p * (membrane_volume_m3(w) - v0);
    };
    sim.run(200);
    const double swing = kinetic_energy_j(w, sim.pool()) + elastic_energy(w, sim.pool()).total_j();
    const double e0 = energy();
    ASSERT_EQ(sim.run(100000).end, RunEnd::completed);
    EXPECT_LT(energy() - e0, 1e-2 * swing);
}

// The SIMD row kernels (forces/membrane_simd.hpp, every instruction set the
// CPU has) give the scalar path's bits: a membrane with its nodes shaken so
// that edges are stretched, slack and of zero length, under both edge laws,
// with rows that do not fill whole blocks of lanes.
TEST(MembraneSimd, NodeForcesGiveTheScalarBits)
{
    const std::vector<SimdKernels> choices = simd_choices();
    if (choices.empty()) GTEST_SKIP() << "neither AVX-512 nor AVX2 on this CPU: the scalar path is the only one";
    const RestoreSimdKernels restore;
    World w;
    w.gravity_m_per_s2 = Vec3::Zero();
    const MembraneSpec spec = small_membrane(10e-3, 13e-3);
    build_membrane(w, spec);
    set_membrane_rigid(w, false);
    w.membrane.pressure_pa = 80e3;
    auto& x = w.bodies[static_cast<std::size_t>(BodyKind::membrane)].x[0];
    ASSERT_GT(w.membrane.columns % 8, 0u) << "rows padded to whole blocks";
    std::uint64_t state = 99;
    auto uniform = [&] { // [−1, 1)
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) * 0x1p-52 - 1.0;
    };
    const double l = spec.mesh_size_m;
    for (Vec3& p : x) {
        // z, y, x: one draw per statement (engine/scene.cpp says why).
        const double z = uniform(), y = uniform();
        p += 0.2 * l * Vec3(uniform(), y, z);
    }
    const auto& e0 = w.membrane.edges[37];
    x[e0[1]] = x[e0[0]]; // an edge of zero length
    const auto bits_of = [](double v) { return std::bit_cast<std::uint64_t>(v); };
    std::size_t stretched = 0, slack = 0;
    for (const MembraneEdgeLaw law : {MembraneEdgeLaw::tension_only, MembraneEdgeLaw::linear}) {
        w.membrane.edge_law = law;
        ThreadPool pool(2);
        set_simd_kernels(SimdKernels::scalar);
        World scalar = w;
        compute_membrane_forces(scalar, pool);
        for (std::size_t e = 0; e < w.membrane.edges.size(); ++e) {
            const double len = (x[w.membrane.edges[e][1]] - x[w.membrane.edges[e][0]]).norm();
            (len > w.membrane.edge_rest_m[e] ? stretched : slack) += 1;
        }
        for (const SimdKernels choice : choices) {
            set_simd_kernels(choice);
            World simd = w;
            compute_membrane_forces(simd, pool);
            const MembraneForces &a = scalar.membrane_forces, &b = simd.membrane_forces;
            SCOPED_TRACE(testing::Message() << "law " << static_cast<int>(law) << ", " << simd_membrane_kernels().lanes << " lanes");
            for (std::size_t i = 0; i < a.node_force_n.size(); ++i)
                for (int c = 0; c < 3; ++c) ASSERT_EQ(bits_of(a.node_force_n[i][c]), bits_of(b.node_force_n[i][c])) << "node " << i;
        }
    }
    EXPECT_GT(stretched, 100u);
    EXPECT_GT(slack, 100u);
}

// The force stage walks the grid with each node's neighbours at fixed column
// offsets (state/membrane.hpp); the element lists say the same mesh one
// element at a time. Summing every element's forces onto its nodes from the
// lists must give the stage's node forces, to the rounding of twelve terms
// summed in another order: a term taken from the wrong neighbour, with the
// wrong sign or missing would be off by a whole element force. Shaken nodes,
// both edge laws, several thread counts and grid sizes (odd and even rows,
// rows that fill the SIMD lanes or not).
TEST(MembraneGrid, NodeForcesAreTheSumOfTheListedElements)
{
    for (const double height : {6e-3, 13e-3}) {
        for (const double radius : {5e-3, 10e-3}) {
            World w;
            w.gravity_m_per_s2 = Vec3::Zero();
            build_membrane(w, small_membrane(radius, height));
            set_membrane_rigid(w, false);
            MembraneMesh& m = w.membrane;
            m.pressure_pa = 30e3;
            auto& x = w.bodies[static_cast<std::size_t>(BodyKind::membrane)].x[0];
            std::uint64_t state = 7;
            auto uniform = [&] { // [−1, 1)
                state = state * 6364136223846793005ull + 1442695040888963407ull;
                return static_cast<double>(state >> 11) * 0x1p-52 - 1.0;
            };
            for (Vec3& p : x) {
                const double z = uniform(), y = uniform();
                p += 0.15e-3 * Vec3(uniform(), y, z);
            }
            for (const MembraneEdgeLaw law : {MembraneEdgeLaw::tension_only, MembraneEdgeLaw::linear}) {
                m.edge_law = law;
                std::vector<Vec3> expected(x.size(), Vec3::Zero());
                std::vector<double> scale(x.size(), 0.0);
                for (std::size_t e = 0; e < m.edges.size(); ++e) {
                    const auto [a, b] = m.edges[e];
                    const Vec3 f = membrane_edge_force_n(x[a], x[b], m.edge_rest_m[e], m.edge_stiffness_n_per_m, law);
                    expected[a] += f, expected[b] -= f;
                    scale[a] += f.norm(), scale[b] += f.norm();
                }
                for (const auto& t : m.triangles) {
                    const Vec3 f = m.pressure_pa / 6.0 * (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
                    for (const std::uint32_t i : t) expected[i] += f, scale[i] += f.norm();
                }
                for (const std::size_t threads : {1, 3}) {
                    ThreadPool pool(threads);
                    World run = w;
                    compute_membrane_forces(run, pool);
                    SCOPED_TRACE(testing::Message() << m.rows << " × " << m.columns << ", law " << static_cast<int>(law)
                                                    << ", " << threads << " threads");
                    for (std::size_t i = 0; i < x.size(); ++i) {
                        ASSERT_GT(scale[i], 0.0) << "node " << i;
                        // Twelve terms: each partial sum rounds by ≤ ½ ulp of
                        // its size, which is at most the sum of |terms|.
                        ASSERT_LE((run.membrane_forces.node_force_n[i] - expected[i]).norm(), 24 * 0x1p-53 * scale[i] * 1.8)
                            << "node " << i;
                    }
                }
            }
        }
    }
}
