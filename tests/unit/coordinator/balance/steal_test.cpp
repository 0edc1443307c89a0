// The mid-frame steal rule: hand-computed cases (equal and unequal paces, a victim nearly
// done, the victim with the most time left rather than the most rows, no paces at all) and
// a randomized search that the rule picks the best whole-unit steal of its model and never
// takes rows the victim has already reached.
#include "coordinator/balance/steal.h"

#include <algorithm>

#include <gtest/gtest.h>

#include "common/base/work_unit.h"
#include "common/sampling/rng.h"

namespace pathfarm::coord {
namespace {

TracerProgress idle_thief(double ms_per_row) { return {1, {}, true, ms_per_row, 0.0}; }

TEST(Steal, NothingWhileTheThiefStillMissesRowsOfItsOwn) {
    const std::vector<TracerProgress> t{{1, {{0, 8}}, true, 0.1, 0.0},
                                        {2, {{8, 64}}, true, 0.1, 0.0}};
    EXPECT_FALSE(choose_steal(1, t, 1.0));
}

TEST(Steal, EqualPacesFinishTogetherAfterTheLatency) {
    // Victim: 32 rows at 0.125 ms = 4 ms. Thief starts 1 ms late: x rows with
    // 4 - 0.125 x = 1 + 0.125 x, x = 12: three units from the tail.
    const auto s = choose_steal(1, {idle_thief(0.125), {2, {{32, 64}}, true, 0.125, 0.0}}, 1.0);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->victim, 2u);
    EXPECT_EQ(s->rows.y0, 52);
    EXPECT_EQ(s->rows.y1, 64);
}

TEST(Steal, AFasterThiefTakesMore) {
    // 4 - 0.125 x = 1 + 0.0625 x: x = 16 rows.
    const auto s = choose_steal(1, {idle_thief(0.0625), {2, {{32, 64}}, true, 0.125, 0.0}}, 1.0);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->rows.y0, 48);
}

TEST(Steal, AVictimNearlyDoneKeepsItsRows) {
    // 2.5 ms since its last news: 20 of its 32 missing rows are done there; 12 rows (1.5 ms)
    // left cannot be split to end the frame a unit (0.5 ms) sooner after a 1 ms latency.
    EXPECT_FALSE(choose_steal(1, {idle_thief(0.125), {2, {{32, 64}}, true, 0.125, 2.5}}, 1.0));
    // 2 ms since: 16 rows left; one unit moves, and the frame ends 0.5 ms sooner.
    const auto s = choose_steal(1, {idle_thief(0.125), {2, {{32, 64}}, true, 0.125, 2.0}}, 1.0);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->rows.y0, 60);
}

TEST(Steal, RowsTheVictimHasReachedAreNotTaken) {
    // 1 ms since news at 0.25 ms/row: rows 32-35 are done or under way; with no latency the
    // thief would take half of what is left, but never rows before 36.
    const auto s = choose_steal(1, {idle_thief(0.25), {2, {{32, 44}}, true, 0.25, 1.0}}, 0.0);
    ASSERT_TRUE(s);
    EXPECT_GE(s->rows.y0, 36);
    EXPECT_EQ(s->rows.y1, 44);
}

TEST(Steal, AVictimWithoutATileIsNotAssumedToHaveRenderedAnything) {
    // The thief rendered 22 rows in 2.2 ms; the victim sent no tile in that time, so it is at
    // least 2.2 / 16 = 0.1375 ms per row slow, and it is on its first unit (rows 22-24): 27
    // rows count, 3.71 ms. Tails from the unit boundaries 44, 40, 36 end the frame at 2.89,
    // 2.34, 2.4 ms: rows 40-50. (Taken as fast as the thief and 22 rows ahead, it would have
    // kept all its rows.)
    const auto s = choose_steal(1, {idle_thief(0.1), {2, {{22, 50}}, true, 0.0, 2.2}}, 1.0);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->rows.y0, 40);
    EXPECT_EQ(s->rows.y1, 50);
}

TEST(Steal, TheVictimIsTheOneWithTheMostTimeLeft) {
    // Tracer 2: 20 rows at 0.3 ms = 6 ms; tracer 3: 28 rows at 0.1 ms = 2.8 ms.
    const auto s = choose_steal(
        1, {idle_thief(0.1), {2, {{0, 20}}, true, 0.3, 0.0}, {3, {{20, 48}}, true, 0.1, 0.0}}, 0.5);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->victim, 2u);
}

TEST(Steal, WithoutPacesRowsStandForTimeAndTheLastGapIsHalved) {
    const auto s = choose_steal(1, {idle_thief(0.0), {2, {{0, 8}, {32, 64}}, true, 0.0, 0.0}}, 5.0);
    ASSERT_TRUE(s);
    // 40 rows missing, all of the last gap unreached: x = 40 / 2 = 20 rows, 5 units.
    EXPECT_EQ(s->rows.y0, 44);
    EXPECT_EQ(s->rows.y1, 64);
}

TEST(Steal, TracersThatCannotTakeAreNeitherThievesNorVictims) {
    EXPECT_FALSE(choose_steal(1, {idle_thief(0.1), {2, {{0, 64}}, false, 0.1, 0.0}}, 0.0));
}

// The rule's model, evaluated for every whole-unit steal from the tail of the last gap.
struct Model {
    double remaining_ms, pace, thief_pace, latency;
    double finish(int rows) const {
        return std::max(remaining_ms - rows * pace, rows > 0 ? latency + rows * thief_pace : 0.0);
    }
};

TEST(Steal, RandomConfigurationsGetTheBestSteal) {
    Pcg32 rng(17);
    int steals = 0, refusals = 0;
    for (int trial = 0; trial < 5000; ++trial) {
        const int height = 8 + 4 * int(rng.next_float() * 60) + int(rng.next_float() * 4);
        const int gap_y1 = height;
        const int gap_y0 = 4 * int(rng.next_float() * float(gap_y1 / 4));
        const int earlier = rng.next_float() < 0.3f ? 4 * int(1 + rng.next_float() * 5) : 0;
        std::vector<RowRange> missing;
        if (earlier > 0 && gap_y0 >= earlier + 4) missing.push_back({0, earlier});
        missing.push_back({gap_y0, gap_y1});
        const double pace = 0.02 + rng.next_float() * 0.5;
        const double thief_pace = 0.02 + rng.next_float() * 0.5;
        int rows = 0;
        for (const RowRange& m : missing)
            rows += m.rows();
        const double since = rng.next_float() * rows * pace;
        const double latency = rng.next_float() * 3.0;
        const auto s =
            choose_steal(1, {idle_thief(thief_pace), {2, missing, true, pace, since}}, latency);
        const double remaining_rows = std::max(0.0, rows - since / pace);
        const Model m{remaining_rows * pace, pace, thief_pace, latency};
        const int reached = gap_y1 - int(std::min(remaining_rows, double(gap_y1 - gap_y0)));
        // The best steal among tails that start on a unit boundary at or after `reached`.
        double best = m.finish(0);
        for (int y0 = gap_y1 - 1; y0 >= reached; --y0)
            if (y0 % kRowsPerWorkUnit == 0) best = std::min(best, m.finish(gap_y1 - y0));
        if (!s) {
            ++refusals;
            EXPECT_GT(best, m.finish(0) - kRowsPerWorkUnit * pace - 1e-9)
                << "trial " << trial << ": a steal a unit better was refused";
            continue;
        }
        ++steals;
        ASSERT_EQ(s->victim, 2u);
        EXPECT_EQ(s->rows.y0 % kRowsPerWorkUnit, 0) << "trial " << trial;
        EXPECT_EQ(s->rows.y1, gap_y1) << "trial " << trial;
        EXPECT_GE(s->rows.y0, reached) << "trial " << trial << ": took rows the victim reached";
        const double got = m.finish(s->rows.rows());
        EXPECT_LE(got, m.finish(0) - kRowsPerWorkUnit * pace + 1e-9) << "trial " << trial;
        EXPECT_LE(got, best + 1e-9) << "trial " << trial << ": a better tail was left";
    }
    EXPECT_GT(steals, 1000);
    EXPECT_GT(refusals, 500);
}

}  // namespace
}  // namespace pathfarm::coord
