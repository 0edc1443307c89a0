// The workload scaler against a farm whose speed changes: frame time = capacity x work.
#include <gtest/gtest.h>

#include "coordinator/pacing/workload_scaler.h"

namespace pathfarm::coord {
namespace {

// Runs `frames` frames at `ms_per_work` and returns the frame times seen.
std::vector<double> run(WorkloadScaler& s, double ms_per_work, int frames) {
    std::vector<double> ms;
    for (int i = 0; i < frames; ++i) {
        ms.push_back(ms_per_work * WorkloadScaler::work(s.level()));
        s.observe(ms.back());
    }
    return ms;
}

TEST(WorkloadScaler, LadderLowersSppThenRouletteThenResolution) {
    WorkloadScaler s({30.0, 8, 0.5f, 0.5f});
    const auto& l = s.ladder();
    ASSERT_GT(l.size(), 5u);
    EXPECT_EQ(l.front().spp, 8);
    for (std::size_t i = 1; i < l.size(); ++i) {
        EXPECT_LT(WorkloadScaler::work(l[i]), WorkloadScaler::work(l[i - 1]));
        if (l[i].rr_scale < 1.0f) {
            EXPECT_EQ(l[i].spp, 1) << "roulette only once spp is 1";
        }
        if (l[i].resolution < 1.0f) {
            EXPECT_EQ(l[i].rr_scale, 0.5f) << "resolution last";
        }
    }
    EXPECT_EQ(l.back().resolution, 0.5f);
    EXPECT_EQ(l.back().rr_scale, 0.5f);
}

TEST(WorkloadScaler, HoldsTheTargetAsCapacityHalvesAndRecovers) {
    WorkloadScaler s({10.0, 8, 0.5f, 0.5f});  // 100 ms frames
    run(s, 20.0, 30);                         // 8 spp would take 160 ms
    auto ms = run(s, 20.0, 10);
    for (double m : ms)
        EXPECT_LE(m, 100.0);
    EXPECT_GE(ms.back(), 55.0) << "and does not leave much of the budget unused";
    const int spp_before = s.level().spp;
    ms = run(s, 40.0, 10);         // a tracer leaves: everything takes twice as long
    EXPECT_GT(ms.front(), 100.0);  // the frame that discovers it
    for (std::size_t i = 1; i < ms.size(); ++i)
        EXPECT_LE(ms[i], 100.0) << "frame " << i << " after the drop";
    EXPECT_LT(s.level().spp, spp_before);
    ms = run(s, 20.0, 30);  // it comes back
    EXPECT_EQ(s.level().spp, spp_before);
}

// Frames of 17 ms that no level changes plus ms_per_work x work, recovering from a slow spell:
// told the render part, the scaler climbs back to within a step of the budget; taking the
// whole frame as scaling with the work, it stops lower (a rise looks costlier than it is).
TEST(WorkloadScaler, UsesTheBudgetAroundAFixedPerFrameCost) {
    const auto settle = [](bool told) {
        WorkloadScaler s({10.0, 4, 0.35f, 0.3f});  // 100 ms frames, 85 ms budget
        double frame = 0.0;
        for (int i = 0; i < 60; ++i) {
            const double render = (i < 20 ? 300.0 : 110.0) * WorkloadScaler::work(s.level());
            frame = 17.0 + render;
            s.observe(frame, told ? render : 0.0);
        }
        return frame;
    };
    const double told = settle(true), untold = settle(false);
    EXPECT_LE(told, 85.0);
    EXPECT_GE(told, 0.8 * 85.0) << "within a ladder step of the budget";
    EXPECT_GT(told, untold + 5.0);
}

TEST(WorkloadScaler, SaysWhenEvenTheFloorIsTooSlow) {
    WorkloadScaler s({30.0, 4, 0.5f, 0.5f});
    run(s, 1000.0, 5);
    EXPECT_TRUE(s.at_floor());
    EXPECT_EQ(s.level().resolution, 0.5f);
    run(s, 1.0, 40);
    EXPECT_FALSE(s.at_floor());
    EXPECT_EQ(s.level().spp, 4);
}

}  // namespace
}  // namespace pathfarm::coord
