// Volume fractions of a column's core (engine/specimen/packing.hpp) on
// packings whose fraction is known exactly.
#include "forces/wire_forces.hpp"
#include "scene.hpp"
#include "specimen/packing.hpp"
#include "state/clump_shape.hpp"
#include "state/world.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace wiredem::engine;

// Clumps count as grains, with the volume of the union of their spheres:
// five clumps of two spheres of radius r whose centres are d = r apart,
// V = 2 (4/3) π r³ − π (4r + d)(2r − d)²/12 (the lens they share counted
// once) = 27/12 π r³, 1.6875 sphere volumes and not 2, beside three free
// spheres, in a box of known volume. The union's volume comes from the mass-properties
// integration, exact for a pair to 2·10⁻¹⁰ (state/clump_shape.hpp).
TEST(GrainVolumes, TwoSphereClumpsCountAsOneGrainEachWithTheirUnionVolume)
{
    World w;
    const std::uint8_t m = add_material(w, Material{10e9, 0.3, 2650.0});
    const double r = 1e-3, d = r;
    const ClumpBody pair = clump_body({{Vec3(-0.5 * d, 0, 0), r}, {Vec3(0.5 * d, 0, 0), r}});
    for (int i = 0; i < 3; ++i) add_grain(w, Vec3(0.01 * i, 0.0, 0.0), r, m);
    for (int i = 0; i < 5; ++i)
        add_clump(w, pair, Vec3(0.01 * i, 0.01, 0.0), Quat(Eigen::AngleAxisd(0.4 * i, Vec3(0, 0, 1))), m);
    ASSERT_EQ(w.of(BodyKind::grain).size(), 3u + 10u);

    const double sphere = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const double lens = std::numbers::pi * (4.0 * r + d) * (2.0 * r - d) * (2.0 * r - d) / 12.0;
    const double clump = 2.0 * sphere - lens;
    const GrainVolumes g = grain_volumes(w);
    ASSERT_EQ(g.volume_m3.size(), 8u);
    EXPECT_EQ(g.volume_m3.size(), grain_body_count(w));
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(g.volume_m3[i], sphere);
        EXPECT_EQ(g.radius_m[i], r);
    }
    for (int i = 3; i < 8; ++i) {
        EXPECT_NEAR(g.volume_m3[i], clump, 1e-9 * clump);
        EXPECT_NEAR(g.radius_m[i], std::cbrt(3.0 * clump / (4.0 * std::numbers::pi)), 1e-9 * r);
    }
    // In a box of 10 mm × 20 mm × 5 mm: the grains' volume fraction.
    const double box_m3 = 10e-3 * 20e-3 * 5e-3;
    EXPECT_NEAR(g.total_volume_m3 / box_m3, (3.0 * sphere + 5.0 * clump) / box_m3, 1e-9 * (3.0 * sphere + 5.0 * clump) / box_m3);
    // 3 + 5 × 1.6875 = 11.4375 sphere volumes, where the spheres' would be 13.
    EXPECT_NEAR(g.total_volume_m3, 11.4375 * sphere, 1e-9 * 11.4375 * sphere);
    // The tests' grain size: each grain once, a clump at 1.6875^(1/3) r (its
    // volume-equivalent radius), not the mean of its 10 spheres' r.
    const double expected = (3.0 * r + 5.0 * std::cbrt(1.6875) * r) / 8.0;
    EXPECT_NEAR(mean_grain_radius_m(w), expected, 1e-9 * r);
    EXPECT_EQ(mean_grain_radius_m(World{}), 0.0);
}

TEST(CoreVolumeFractions, ASimpleCubicLatticeFillsPiOverSix)
{
    // Touching spheres of radius r on a cubic lattice of spacing 2r fill
    // π/6 = 0.5236 of space; the core (a cylinder of radius 6 spacings and
    // 10 tall, inside the lattice's ±8 and 0–16 spacings) samples it on a grid of 0.1 r, whose error is
    // of the order of the grid spacing over the radius times the surface
    // fraction: 1 % here.
    World w;
    const std::uint8_t m = add_material(w, Material{});
    const double r = 1e-3, a = 2.0 * r;
    for (int i = -8; i <= 8; ++i)
        for (int j = -8; j <= 8; ++j)
            for (int k = 0; k <= 16; ++k) add_grain(w, Vec3(i * a, j * a, k * a), r, m);
    const CoreFractions f = core_volume_fractions(w, 9 * a, 0.0, 16 * a, 3 * a, 0.1 * r);
    EXPECT_NEAR(f.grain, std::numbers::pi / 6.0, 0.01);
    EXPECT_EQ(f.wire, 0.0);
    EXPECT_NEAR(f.volume_m3, std::numbers::pi * (6 * a) * (6 * a) * (10 * a), 1e-18);
}

TEST(CoreVolumeFractions, AWireCountsAsACylinderAlongTheSegmentsInTheCore)
{
    // A straight vertical wire of 41 nodes 1 mm apart on the axis, from
    // z = 0 to 40 mm; the core runs from 5 to 35 mm: the 30 segments whose
    // midpoints lie in it count, π r_w² · 30 mm.
    World w;
    WireSpec spec;
    spec.radius_m = 0.4e-3;
    spec.segment_length_m = 1e-3;
    configure_wire(w, spec);
    for (int i = 0; i <= 40; ++i) append_wire_node(w, Vec3(0.0, 0.0, i * 1e-3));
    const CoreFractions f = core_volume_fractions(w, 20e-3, 0.0, 40e-3, 5e-3, 1e-3);
    const double core_m3 = std::numbers::pi * 15e-3 * 15e-3 * 30e-3;
    EXPECT_NEAR(f.wire, std::numbers::pi * 0.4e-3 * 0.4e-3 * 30e-3 / core_m3, 1e-15);
    EXPECT_EQ(f.grain, 0.0);
    // An empty core (margins larger than the column) gives zeros, not NaN.
    const CoreFractions none = core_volume_fractions(w, 20e-3, 0.0, 40e-3, 25e-3, 1e-3);
    EXPECT_EQ(none.wire, 0.0);
    EXPECT_EQ(none.volume_m3, 0.0);
}

TEST(CoreVolumeFractions, TheBoxsCoreLeavesOutTheLayersAtItsWalls)
{
    // The rigid-wall cell's core: the same lattice (π/6, grid error 1 %)
    // inside a box whose walls stand 3 spacings beyond it on every side, an
    // empty layer as a wall's loose layer would be. The whole box holds
    // 17³ (4/3) π r³ in (22 a)³: 0.242. Its core, a margin of 4 spacings in
    // from every wall, lies inside the lattice: π/6 again.
    World w;
    const std::uint8_t m = add_material(w, Material{});
    const double r = 1e-3, a = 2.0 * r;
    for (int i = -8; i <= 8; ++i)
        for (int j = -8; j <= 8; ++j)
            for (int k = 0; k <= 16; ++k) add_grain(w, Vec3(i * a, j * a, k * a), r, m);
    const Vec3 lo(-11 * a, -11 * a, -3 * a), hi(11 * a, 11 * a, 19 * a);
    const CoreFractions core = box_core_volume_fractions(w, lo, hi, 4 * a, 0.1 * r);
    EXPECT_NEAR(core.grain, std::numbers::pi / 6.0, 0.01);
    EXPECT_EQ(core.wire, 0.0);
    EXPECT_NEAR(core.volume_m3, (14 * a) * (14 * a) * (14 * a), 1e-18);
    // With no margin the grid sees the whole box: the empty layers count.
    const double whole = 17.0 * 17.0 * 17.0 * (4.0 / 3.0) * std::numbers::pi * r * r * r / std::pow(22 * a, 3);
    EXPECT_NEAR(box_core_volume_fractions(w, lo, hi, 0.0, 0.1 * r).grain, whole, 0.01 * whole);
    // A margin of half the box or more leaves no core: zeros, not NaN.
    const CoreFractions none = box_core_volume_fractions(w, lo, hi, 11 * a, 0.1 * r);
    EXPECT_EQ(none.grain, 0.0);
    EXPECT_EQ(none.volume_m3, 0.0);
}

TEST(CoreVolumeFractions, BothCellsSampleTheirCoreOneWay)
{
    // A diameter of the largest grain in from the walls; every 0.1 r_p, or
    // 0.05 D50 (by mass) with a curve.
    const CoreSampling spheres = core_sampling(largest_grain_radius_m(1e-3, 0.2, std::nullopt, std::nullopt), 1e-3, std::nullopt);
    EXPECT_DOUBLE_EQ(spheres.margin_m, 2.0 * 1.2e-3);
    EXPECT_DOUBLE_EQ(spheres.grid_m, 1e-4);
    SieveCurve curve;
    curve.diameters_m = {1e-3, 4e-3};
    curve.fraction_passing = {0.0, 1.0};
    const CoreSampling graded = core_sampling(largest_grain_radius_m(1e-3, 0.2, curve, std::nullopt), 1e-3, curve);
    EXPECT_DOUBLE_EQ(graded.margin_m, 4e-3);
    EXPECT_DOUBLE_EQ(graded.grid_m, 0.05 * GrainSizeDistribution(curve).diameter_at_mass_fraction(0.5));
    // A clump reaches its bounding radius.
    const ClumpBody pair = clump_body({{Vec3(-0.5e-3, 0, 0), 1e-3}, {Vec3(0.5e-3, 0, 0), 1e-3}});
    EXPECT_DOUBLE_EQ(largest_grain_radius_m(1e-3, 0.0, std::nullopt, pair), pair.bounding_radius_m() * 1e-3);
}
