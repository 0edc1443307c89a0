// Balancers: exact coverage in work units for any tracer count and height, tracers joining and
// leaving, and the hand-computed shares of Perfect, Perfect Smooth, Robin Hood and ours.
#include "coordinator/balance/balancer.h"

#include <gtest/gtest.h>

#include "common/sampling/rng.h"

namespace pathfarm::coord {
namespace {

void expect_exact_cover(const std::vector<RowRange>& ranges, int height, std::size_t tracers,
                        const std::string& what) {
    ASSERT_EQ(ranges.size(), tracers) << what;
    int y = 0;
    for (const RowRange& r : ranges) {
        ASSERT_EQ(r.y0, y) << what << ": contiguous, in order";
        ASSERT_GE(r.y1, r.y0) << what;
        // Non-empty ranges start on unit boundaries; a tracer without work gets an empty range.
        ASSERT_TRUE(r.empty() || r.y0 % kRowsPerWorkUnit == 0)
            << what << ": starts on a unit boundary";
        y = r.y1;
    }
    ASSERT_EQ(y, height) << what << ": covers every row exactly once";
}

TEST(Balancers, CoverEveryRowOnceWhileTracersComeAndGo) {
    Pcg32 rng(5);
    for (const std::string& name : balancer_names()) {
        for (int height : {1, 3, 4, 50, 97, 360}) {
            auto balancer = make_balancer(name);
            std::vector<TracerFrame> last;
            std::vector<double> speed;
            for (int frame = 0; frame < 40; ++frame) {
                // Every few frames a tracer joins or leaves (1 to 64 tracers).
                const std::size_t n = 1 + std::size_t(frame / 5 * 7 % 64);
                last.resize(n);
                speed.resize(n, 1.0);
                for (double& s : speed)
                    s = s > 0.0 ? s : 0.2 + rng.next_float();
                BalanceInput in{height, last, {}};
                in.unit_cost.assign(std::size_t(work_units(height)), 1.0);
                for (double& c : in.unit_cost)
                    c = 0.5 + rng.next_float();
                const auto ranges = balancer->assign(in);
                expect_exact_cover(
                    ranges, height, n,
                    name + " h=" + std::to_string(height) + " n=" + std::to_string(n));
                for (std::size_t i = 0; i < n; ++i) {  // what this frame "measured"
                    double cost = 0.0;
                    for (int u = ranges[i].y0 / 4; u < (ranges[i].y1 + 3) / 4; ++u)
                        cost += in.unit_cost[std::size_t(u)];
                    last[i] =
                        TracerFrame{ranges[i], ranges[i].empty() ? 0.0 : 1.0 + cost / speed[i]};
                }
            }
        }
    }
}

TEST(Balancers, PerfectMatchesHandComputedShares) {
    // 80 rows = 20 units. Tracer 0 did 10 units in 10 ms, tracer 1 10 units in 20 ms: speeds 1
    // and 0.5 units/ms, shares 2/3 and 1/3: 13.33 and 6.67 units, largest remainder -> 13 and 7.
    const BalanceInput in{80, {{{0, 40}, 10.0}, {{40, 80}, 20.0}}, {}};
    EXPECT_EQ(make_balancer("perfect")->assign(in), (std::vector<RowRange>{{0, 52}, {52, 80}}));
}

TEST(Balancers, PerfectSmoothBlendsShares) {
    auto smooth = make_balancer("perfect-smooth", 0.5);
    // First frame: S = P = (2/3, 1/3).
    const BalanceInput first{80, {{{0, 40}, 10.0}, {{40, 80}, 20.0}}, {}};
    EXPECT_EQ(smooth->assign(first), (std::vector<RowRange>{{0, 52}, {52, 80}}));
    // Now equal speeds: P = (1/2, 1/2), S = 0.5 P + 0.5 S = (7/12, 5/12) -> 11.67 and 8.33 units
    // -> 12 and 8 by largest remainder.
    const BalanceInput second{80, {{{0, 52}, 13.0}, {{52, 80}, 7.0}}, {}};
    EXPECT_EQ(smooth->assign(second), (std::vector<RowRange>{{0, 48}, {48, 80}}));
}

TEST(Balancers, RobinHoodPassesOneUnitFromLastToFirstFinisher) {
    const BalanceInput in{80, {{{0, 40}, 30.0}, {{40, 60}, 10.0}, {{60, 80}, 20.0}}, {}};
    EXPECT_EQ(make_balancer("robin-hood")->assign(in),
              (std::vector<RowRange>{{0, 36}, {36, 60}, {60, 80}}));
}

TEST(Balancers, CostPredictiveEqualisesPredictedFinishTimes) {
    // 40 rows = 10 units; the first 5 units cost 3, the rest 1 (total 20). Equal speeds (each did
    // half the cost in the same time): the cut falls where the cost reaches 10 -> after 3.33
    // units of cost 3 -> 3 units (cost 9) vs 7 units (cost 11) or 4 (12) vs 6 (8): 3 is nearer.
    BalanceInput in{40, {{{0, 12}, 9.0}, {{12, 40}, 11.0}}, {3, 3, 3, 3, 3, 1, 1, 1, 1, 1}};
    EXPECT_EQ(make_balancer("cost-predictive")->assign(in),
              (std::vector<RowRange>{{0, 12}, {12, 40}}));
    // Tracer 1 twice as fast: targets 20/3 and 40/3 of cost -> cut after 2 units (cost 6).
    in.last = {{{0, 12}, 9.0}, {{12, 40}, 5.5}};
    EXPECT_EQ(make_balancer("cost-predictive")->assign(in),
              (std::vector<RowRange>{{0, 8}, {8, 40}}));
}

TEST(Balancers, CostPredictivePrefersTheDeliveredCostRate) {
    // Same cost map; the ranges and times say equal speeds, but rows moved mid-frame and each
    // tracer reports what it really delivered per ms: tracer 1 twice as fast, as above.
    BalanceInput in{
        40, {{{0, 12}, 9.0, 1.0}, {{12, 40}, 11.0, 2.0}}, {3, 3, 3, 3, 3, 1, 1, 1, 1, 1}};
    EXPECT_EQ(make_balancer("cost-predictive")->assign(in),
              (std::vector<RowRange>{{0, 8}, {8, 40}}));
}

TEST(Balancers, CostPredictiveCutsWhereBothFinishSoonest) {
    // Ten units of cost 1; tracer 0 delivers 0.5625 per ms, tracer 1 1.0: its share is 3.6
    // units. Four units end it at 7.1 ms (the rest at 6); three at 5.3 (the rest at 7): the
    // nearest boundary in cost (4) ends the frame later.
    BalanceInput in{
        40, {{{0, 20}, 1.0, 0.5625}, {{20, 40}, 1.0, 1.0}}, std::vector<double>(10, 1.0)};
    EXPECT_EQ(make_balancer("cost-predictive")->assign(in),
              (std::vector<RowRange>{{0, 12}, {12, 40}}));
}

TEST(Balancers, UnknownNameIsNull) { EXPECT_EQ(make_balancer("magic"), nullptr); }

}  // namespace
}  // namespace pathfarm::coord
