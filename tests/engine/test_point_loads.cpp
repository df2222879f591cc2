// The point loads' list (state/point_loads.hpp) stays in body order, each
// body at most once, whichever way it is written; a list that is not is
// refused with a message naming the entries.
#include "state/point_loads.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace wiredem::engine;

namespace {

/// The bodies of `loads`, in list order.
std::vector<BodyRef> bodies_of(const PointLoads& loads)
{
    std::vector<BodyRef> out;
    for (const auto& [body, f] : loads) out.push_back(body);
    return out;
}

const BodyRef grain_3(BodyKind::grain, 3), grain_9(BodyKind::grain, 9), wire_0(BodyKind::wire, 0),
    wire_5(BodyKind::wire, 5), membrane_2(BodyKind::membrane, 2);

} // namespace

TEST(PointLoads, SetKeepsBodyOrderAndOneLoadPerBody)
{
    PointLoads loads;
    loads.set(wire_5, Vec3(0, 0, -1));
    loads.set(grain_9, Vec3(1, 0, 0));
    loads.set(membrane_2, Vec3(0, 2, 0));
    loads.set(grain_3, Vec3(3, 0, 0));
    loads.set(wire_0, Vec3(0, 0, -4));
    EXPECT_EQ(bodies_of(loads), (std::vector<BodyRef>{grain_3, grain_9, wire_0, wire_5, membrane_2}));
    loads.set(grain_9, Vec3(0, 0, 7)); // replaces, does not add
    ASSERT_EQ(loads.size(), 5u);
    EXPECT_EQ(loads[1].second, Vec3(0, 0, 7));
    EXPECT_EQ(loads[3].second, Vec3(0, 0, -1));
}

TEST(PointLoads, OfGivesTheLoadsOfOneKindsIndexRange)
{
    PointLoads loads;
    for (BodyRef b : {grain_3, grain_9, wire_0, wire_5, membrane_2}) loads.set(b, Vec3::UnitZ());
    EXPECT_EQ(loads.of(BodyKind::grain, 0, 10).size(), 2u);
    EXPECT_EQ(loads.of(BodyKind::grain, 3, 9).size(), 1u); // [3, 9): grain 9 is the next block's
    EXPECT_EQ(loads.of(BodyKind::grain, 9, 10).front().first, grain_9);
    EXPECT_TRUE(loads.of(BodyKind::grain, 4, 9).empty());
    EXPECT_EQ(loads.of(BodyKind::wire, 0, 6).size(), 2u);
    EXPECT_EQ(loads.of(BodyKind::wire, 1, BodyRef::max_index + 1).front().first, wire_5);
    EXPECT_EQ(loads.of(BodyKind::membrane, 0, BodyRef::max_index + 1).size(), 1u);
    EXPECT_TRUE(PointLoads{}.of(BodyKind::wire, 0, 100).empty());
}

TEST(PointLoads, OfFindsTheLoadsOfConsecutiveBodiesByIndex)
{
    // Every wire node from 2 to 11 loaded (the wire's weight names every
    // node): found by index; a grain on either side of them.
    PointLoads loads;
    loads.set(grain_3, Vec3::UnitX());
    for (std::uint32_t i = 2; i < 12; ++i) loads.set(BodyRef(BodyKind::wire, i), Vec3(0, 0, -static_cast<double>(i)));
    loads.set(membrane_2, Vec3::UnitY());
    const auto middle = loads.of(BodyKind::wire, 5, 9);
    ASSERT_EQ(middle.size(), 4u);
    EXPECT_EQ(middle.front().first, BodyRef(BodyKind::wire, 5));
    EXPECT_EQ(middle.back().second, Vec3(0, 0, -8));
    EXPECT_EQ(loads.of(BodyKind::wire, 0, 4).size(), 2u);  // nodes 2 and 3
    EXPECT_EQ(loads.of(BodyKind::wire, 10, 256).size(), 2u); // 10 and 11
    EXPECT_TRUE(loads.of(BodyKind::wire, 0, 2).empty());
    EXPECT_TRUE(loads.of(BodyKind::wire, 12, 256).empty());
    EXPECT_EQ(loads.of(BodyKind::wire, 0, BodyRef::max_index + 1).size(), 10u);
    loads.set(BodyRef(BodyKind::wire, 20), Vec3::UnitZ()); // no longer consecutive: searched
    EXPECT_EQ(loads.of(BodyKind::wire, 5, 9).size(), 4u);
    EXPECT_EQ(loads.of(BodyKind::wire, 10, 256).size(), 3u);
    loads.clear();
    EXPECT_TRUE(loads.of(BodyKind::wire, 0, 256).empty());
}

TEST(PointLoads, AListOutOfBodyOrderIsRefusedNamingTheEntries)
{
    const Vec3 f(0, 0, -1);
    const auto sorted = PointLoads::from_sorted({{grain_3, f}, {wire_0, f}, {wire_5, f}});
    ASSERT_TRUE(sorted.ok()) << sorted.error();
    EXPECT_EQ(bodies_of(sorted.value()), (std::vector<BodyRef>{grain_3, wire_0, wire_5}));

    const auto swapped = PointLoads::from_sorted({{grain_3, f}, {wire_5, f}, {wire_0, f}});
    ASSERT_FALSE(swapped.ok());
    EXPECT_NE(swapped.error().find("entry 2 (wire node 0) comes before entry 1 (wire node 5)"), std::string::npos)
        << swapped.error();
    EXPECT_NE(swapped.error().find("sorted by body"), std::string::npos) << swapped.error();

    const auto twice = PointLoads::from_sorted({{grain_3, f}, {grain_3, 2.0 * f}});
    ASSERT_FALSE(twice.ok());
    EXPECT_NE(twice.error().find("entry 1 (grain 3) names the body of entry 0 (grain 3)"), std::string::npos)
        << twice.error();
    EXPECT_NE(twice.error().find("each body at most once"), std::string::npos) << twice.error();
}
