// Latency bookkeeping: each input is timed to the first frame that echoes it.
#include <gtest/gtest.h>

#include "client/latency_stats.h"

namespace pathfarm::client {
namespace {

using namespace std::chrono_literals;

TEST(LatencyStats, TimesEachInputToTheFirstFrameThatEchoesIt) {
    LatencyStats s;
    const auto t0 = LatencyStats::Clock::time_point{} + 1s;
    s.input_sent(1, t0);
    s.input_sent(2, t0 + 10ms);
    s.frame_arrived(0, 0, t0 + 33ms);  // echoes nothing yet
    s.frame_arrived(1, 1, t0 + 66ms);  // input 1: 66 ms
    s.input_sent(3, t0 + 70ms);
    s.frame_arrived(2, 3, t0 + 100ms);  // inputs 2 (90 ms) and 3 (30 ms)
    s.frame_arrived(3, 3, t0 + 133ms);  // nothing new
    const LatencySummary l = s.summary();
    EXPECT_EQ(l.inputs, 3u);
    EXPECT_EQ(l.frames, 4u);
    EXPECT_NEAR(l.latency_p50_ms, 66.0, 1e-9);
    EXPECT_NEAR(l.latency_p99_ms, 90.0, 1e-9);
    EXPECT_NEAR(l.interval_p50_ms, 33.0, 1e-9);
    EXPECT_NEAR(l.interval_p99_ms, 34.0, 1e-9);
}

TEST(LatencyStats, QuantileByNearestRank) {
    EXPECT_EQ(quantile({}, 0.5), 0.0);
    EXPECT_EQ(quantile({5, 1, 3}, 0.5), 3.0);
    EXPECT_EQ(quantile({5, 1, 3}, 0.99), 5.0);
    EXPECT_EQ(quantile({5, 1, 3}, 0.0), 1.0);
}

}  // namespace
}  // namespace pathfarm::client
