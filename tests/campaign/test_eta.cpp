// The time left of a campaign (campaign/eta.hpp): steps left over the rate
// measured in this process, from its first report on.
#include "eta.hpp"

#include <gtest/gtest.h>

namespace wiredem::campaign {
namespace {

TEST(Eta, NothingIsClaimedBeforeAStepIsMeasuredThenStepsLeftOverTheRate)
{
    EtaEstimate eta;
    EXPECT_FALSE(eta.update(0.0, {0.0, 1e6, false}));  // 0 %: no rate yet
    EXPECT_FALSE(eta.update(2.0, {0.0, 1e6, false}));  // still nothing run (loading files)
    // 500 steps in 5 s: 100 steps/s, 999 500 left → 9995 s, though the job
    // is at 0.05 % (elapsed × (1 − f) / f would say nothing below 1 %).
    const auto e = eta.update(5.0, {500.0, 999'500.0, false});
    ASSERT_TRUE(e);
    EXPECT_DOUBLE_EQ(*e, 9995.0);
}

TEST(Eta, AResumedRunIsTimedFromItsOwnStepsNotFromTheProgressEarlierRunsMade)
{
    // An earlier run did 60 % of the work; this one starts at 60 % and runs
    // 1000 steps in its first 10 s: 100 steps/s. The 400 000 steps left take
    // 4000 s. Extrapolating 60 % done in 10 s would say ~7 s.
    EtaEstimate eta;
    EXPECT_FALSE(eta.update(0.0, {0.0, 401'000.0, false}));
    const auto e = eta.update(10.0, {1000.0, 400'000.0, false});
    ASSERT_TRUE(e);
    EXPECT_DOUBLE_EQ(*e, 4000.0);
}

TEST(Eta, TheTestsRateIsMeasuredAfreshWhenTheyBegin)
{
    // The pour ran 10 000 (estimated) steps/s; the tests run 100: once they
    // have, the time left is theirs, not the pour's.
    EtaEstimate eta;
    (void)eta.update(0.0, {0.0, 200'000.0, false});
    EXPECT_DOUBLE_EQ(*eta.update(10.0, {100'000.0, 100'000.0, false}), 10.0);
    EXPECT_FALSE(eta.update(10.5, {100'000.0, 100'000.0, true}));  // the tests' first report
    EXPECT_DOUBLE_EQ(*eta.update(20.5, {101'000.0, 99'000.0, true}), 990.0);
}

TEST(Eta, NothingLeftIsNoTimeLeft)
{
    EtaEstimate eta;
    (void)eta.update(0.0, {0.0, 10.0, false});
    EXPECT_EQ(eta.update(1.0, {10.0, 0.0, false}), 0.0);
}

} // namespace
} // namespace wiredem::campaign
