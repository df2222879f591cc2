// Cuts where a reference test's wire strain was lowest (issue 39,
// engine/analysis/cut_selection.hpp): on synthetic strain profiles with
// known minima, and the loop length of a helix.
#include "analysis/cut_selection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

using namespace wiredem::engine;
using namespace wiredem::engine::analysis;

namespace {

/// A profile with a minimum every `period` segments, each deeper than the
/// one before: ε_s = cos(2π s/P) (1 + 10⁻³ s); minima at s = P/2 + kP.
std::vector<double> wavy_profile(int segments, int period)
{
    std::vector<double> e(segments);
    for (int s = 0; s < segments; ++s) e[s] = std::cos(2.0 * std::numbers::pi * s / period) * (1.0 + 1e-3 * s);
    return e;
}

} // namespace

// Minima at 20, 60, 100, 140, 180 (P = 40), deepest last: the three lowest
// a period apart and a period from the ends (180 is 20 segments from the
// end) are 140, 100 and 60, returned in ascending order at the segments'
// middles.
TEST(CutSelection, PicksTheDeepestMinimaAtLeastTheSpacingApart)
{
    const double l_w = 1.25e-3;
    const std::vector<double> e = wavy_profile(200, 40);
    const auto cuts = lowest_strain_cuts(e, l_w, 3, 40 * l_w);
    ASSERT_EQ(cuts.size(), 3u);
    EXPECT_EQ(cuts[0].segment, 60u);
    EXPECT_EQ(cuts[1].segment, 100u);
    EXPECT_EQ(cuts[2].segment, 140u);
    EXPECT_DOUBLE_EQ(cuts[0].position_m, 60.5 * l_w);
    EXPECT_EQ(cuts[2].strain, e[140]);
    // No spacing: the three lowest segments, all beside the deepest minimum.
    const auto close = lowest_strain_cuts(e, l_w, 3, 0.0);
    ASSERT_EQ(close.size(), 3u);
    EXPECT_EQ(close[0].segment, 179u);
    EXPECT_EQ(close[1].segment, 180u);
    EXPECT_EQ(close[2].segment, 181u);
}

// At most as many places as fit: every cut a spacing from the others and
// from the two ends. With a spacing of 50 segments only the minima at 60,
// 140 (or 100) fit; the deepest at 180 is 20 segments from the end.
TEST(CutSelection, KeepsTheSpacingFromTheEndsAndReturnsWhatFits)
{
    const double l_w = 1.0;
    const std::vector<double> e = wavy_profile(200, 40);
    const auto cuts = lowest_strain_cuts(e, l_w, 5, 50.0);
    ASSERT_EQ(cuts.size(), 2u);
    EXPECT_EQ(cuts[0].segment, 60u);
    EXPECT_EQ(cuts[1].segment, 140u);
    for (const CutPlace& c : cuts) {
        EXPECT_GE(c.position_m, 50.0);
        EXPECT_GE(200.0 - c.position_m, 50.0);
    }
}

// A segment removed already (strain 0 reported) is never chosen.
TEST(CutSelection, SkipsExcludedSegments)
{
    std::vector<double> e(20, 0.01);
    e[7] = -0.5;
    e[12] = -0.2;
    std::vector<std::uint8_t> removed(20, 0);
    removed[7] = 1;
    const auto cuts = lowest_strain_cuts(e, 1.0, 1, 0.0, removed);
    ASSERT_EQ(cuts.size(), 1u);
    EXPECT_EQ(cuts[0].segment, 12u);
}

// Nodes laid l_w apart along a circle of radius R (the helix's plan): the
// rest length per loop is 2πR; a wire winding less than a loop has none.
TEST(CutSelection, AHelixsLoopIsItsCircumference)
{
    const double r = 4e-3, l_w = 1.25e-3, rise = 0.1e-3;
    std::vector<Vec3> x;
    for (int i = 0; i < 200; ++i) {
        const double phi = i * l_w / r;
        x.emplace_back(r * std::cos(phi), r * std::sin(phi), i * rise);
    }
    EXPECT_NEAR(length_per_loop_m(x, l_w), 2.0 * std::numbers::pi * r, 1e-12);
    x.resize(10); // 10 nodes: 9 × 0.3125 rad < 2π
    EXPECT_EQ(length_per_loop_m(x, l_w), 0.0);
}
