// The cuboid cell's test stopped and continued (checkpoints): a test stopped
// between any two steps — in the ramp, the hold or the loading — and
// continued from the World and the driver's state saved there ends exactly
// as the test that was never stopped, on any number of threads: the same
// rows (the membrane cell's and the box's), servo figures and final state,
// bit for bit. The campaign's resume of a killed cuboid test rests on this
// (campaign/stages.cpp; the state's file round trip: CampaignFiles.*).
#include "fcc.hpp"
#include "state/state_hash.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

using namespace wiredem::engine;
using namespace wiredem::engine::validation;

TEST(CuboidCell, ATestContinuedFromAnyStepEndsBitIdentically)
{
    CuboidSettings set = fcc_settings();
    set.triaxial.target_axial_strain = 0.005; // the stops are what is tested, not the peak
    Simulation whole(2);
    const CuboidWalls walls = fcc_world(whole, 0.3);
    const World start = whole.world;

    // The uninterrupted run, saving World and state at three steps: in the
    // ramp, in the hold and during loading.
    std::vector<std::uint64_t> stops;
    std::vector<std::pair<World, CuboidDriverState>> saved;
    CuboidContinuation c;
    c.between_steps = [&](const World& w, const CuboidDriverState& st) {
        const double t = static_cast<double>(st.triaxial.steps) * w.dt_s;
        const TriaxialSettings& s = set.triaxial;
        const bool in_ramp = saved.empty() && t > 0.5 * s.pressure_ramp_time_s;
        const bool in_hold = saved.size() == 1 && t > s.pressure_ramp_time_s + 0.5 * s.hold_time_s;
        const bool loading = saved.size() == 2 && st.triaxial.loading
                          && st.triaxial.result.series.size() > st.triaxial.loading_start_sample + 3;
        if (in_ramp || in_hold || loading) {
            saved.emplace_back(w, st);
            stops.push_back(st.triaxial.steps);
        }
    };
    const auto full = run_cuboid_triaxial(whole, walls, set, {}, c);
    ASSERT_TRUE(full.ok()) << full.error();
    ASSERT_EQ(saved.size(), 3u);
    EXPECT_FALSE(saved[0].second.triaxial.loading);
    EXPECT_FALSE(saved[1].second.triaxial.loading);
    EXPECT_TRUE(saved[2].second.triaxial.loading);
    const std::uint64_t end_hash = state_hash(whole.world);
    const CuboidResult& f = full.value();

    for (std::size_t k = 0; k < saved.size(); ++k) {
        SCOPED_TRACE("continued from step " + std::to_string(stops[k]));
        Simulation rest(1 + k % 3); // any thread count
        rest.world = saved[k].first;
        CuboidContinuation from;
        from.from = saved[k].second;
        const auto r = run_cuboid_triaxial(rest, walls, set, {}, from);
        ASSERT_TRUE(r.ok()) << r.error();
        const CuboidResult& g = r.value();
        EXPECT_EQ(state_hash(rest.world), end_hash);
        EXPECT_EQ(g.triaxial.steps, f.triaxial.steps);
        EXPECT_EQ(g.triaxial.hold_time_s, f.triaxial.hold_time_s);
        EXPECT_EQ(g.triaxial.initial_height_m, f.triaxial.initial_height_m);
        EXPECT_EQ(g.triaxial.consolidated_sigma1_pa, f.triaxial.consolidated_sigma1_pa);
        EXPECT_EQ(g.triaxial.peak_deviatoric_stress_pa, f.triaxial.peak_deviatoric_stress_pa);
        EXPECT_EQ(g.triaxial.snapshots.size(), f.triaxial.snapshots.size());
        EXPECT_EQ(g.triaxial.series.time_s, f.triaxial.series.time_s);
        EXPECT_EQ(g.triaxial.series.phase, f.triaxial.series.phase);
        EXPECT_EQ(g.triaxial.series.sigma1_pa, f.triaxial.series.sigma1_pa);
        EXPECT_EQ(g.triaxial.series.sigma3_effective_pa, f.triaxial.series.sigma3_effective_pa);
        EXPECT_EQ(g.triaxial.series.volumetric_strain, f.triaxial.series.volumetric_strain);
        EXPECT_EQ(g.width_x_m, f.width_x_m);
        EXPECT_EQ(g.sigma_y_pa, f.sigma_y_pa);
        EXPECT_EQ(g.servo_max_deviation, f.servo_max_deviation);
        EXPECT_EQ(g.servo_mean_deviation, f.servo_mean_deviation);
    }

    // A test never stopped, run again from the start, gives the same end;
    // a saved state that does not fit the World is refused, not run.
    Simulation again(3);
    again.world = start;
    ASSERT_TRUE(run_cuboid_triaxial(again, walls, set).ok());
    EXPECT_EQ(state_hash(again.world), end_hash);
    Simulation bad(1);
    bad.world = saved[2].first;
    CuboidContinuation torn;
    torn.from = saved[2].second;
    torn.from->sigma_x_pa.pop_back();
    const auto refused = run_cuboid_triaxial(bad, walls, set, {}, torn);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().find("saved state is inconsistent"), std::string::npos) << refused.error();
}
