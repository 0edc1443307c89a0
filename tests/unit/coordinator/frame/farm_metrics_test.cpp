// The farm's metrics as Prometheus text (the integration test parses a live /metrics with
// Prometheus' own parser and checks it against the CSVs).
#include <gtest/gtest.h>

#include "coordinator/frame/farm_metrics.h"

namespace pathfarm::coord {
namespace {

bool has_line(const std::string& text, const std::string& line) {
    return text.find("\n" + line + "\n") != std::string::npos || text.rfind(line + "\n", 0) == 0;
}

TEST(FarmMetrics, HistogramBucketsAreCumulativeAndInclusive) {
    Histogram h({0.1, 0.2});
    for (const double v : {0.05, 0.1, 0.15, 0.2, 0.25, 3.0})
        h.observe(v);
    std::string out;
    h.render(out, "x_seconds", "help");
    EXPECT_TRUE(has_line(out, "# TYPE x_seconds histogram"));
    EXPECT_TRUE(has_line(out, "x_seconds_bucket{le=\"0.1\"} 2"));
    EXPECT_TRUE(has_line(out, "x_seconds_bucket{le=\"0.2\"} 4"));
    EXPECT_TRUE(has_line(out, "x_seconds_bucket{le=\"+Inf\"} 6"));
    EXPECT_TRUE(has_line(out, "x_seconds_count 6"));
    EXPECT_TRUE(has_line(out, "x_seconds_sum 3.75"));
}

TEST(FarmMetrics, FramesTracersAndClients) {
    FarmMetrics m;
    m.observe_frame({true, 40.0, 2, 100, 1000, {{"a", 0.5, 12}, {"b\"\n", 0.25, 8}}});
    m.observe_frame({true, 60.0, 2, 50, 2000, {{"a", 0.75, 10}, {"b\"\n", 1.0, 10}}});
    m.observe_frame({false, 0.0, 1, 10, 0, {}});  // converged: counted, not timed
    m.set_clients(1, 2);
    const std::string t = m.text();
    EXPECT_TRUE(has_line(t, "pathfarm_frames_total 3"));
    EXPECT_TRUE(has_line(t, "pathfarm_frame_seconds_count 2"));
    EXPECT_TRUE(has_line(t, "pathfarm_frame_seconds_sum 0.1"));
    EXPECT_TRUE(has_line(t, "pathfarm_tracers 1"));
    EXPECT_TRUE(has_line(t, "pathfarm_commit_bytes_total 160"));
    EXPECT_TRUE(has_line(t, "pathfarm_tile_bytes_total 3000"));
    EXPECT_TRUE(has_line(t, "pathfarm_tracer_busy_ratio{tracer=\"a\"} 0.75"));
    EXPECT_TRUE(has_line(t, "pathfarm_tracer_rows_total{tracer=\"a\"} 22"));
    EXPECT_TRUE(has_line(t, "pathfarm_tracer_rows_total{tracer=\"b\\\"\\n\"} 18"));
    EXPECT_TRUE(has_line(t, "pathfarm_clients{kind=\"native\"} 1"));
    EXPECT_TRUE(has_line(t, "pathfarm_clients{kind=\"browser\"} 2"));
}

// A tracer that renders nothing in a frame (the others took its rows, or it left) is idle in
// that frame, and its row counter keeps its count: a Prometheus counter never goes back (it
// used to restart from zero, which a loaded farm showed in the metrics test).
TEST(FarmMetrics, ATracersRowCounterNeverGoesBack) {
    FarmMetrics m;
    m.observe_frame({true, 40.0, 2, 0, 0, {{"a", 0.5, 12}, {"b", 0.5, 8}}});
    m.observe_frame({true, 40.0, 2, 0, 0, {{"a", 0.5, 12}}});
    std::string t = m.text();
    EXPECT_TRUE(has_line(t, "pathfarm_tracer_rows_total{tracer=\"a\"} 24"));
    EXPECT_TRUE(has_line(t, "pathfarm_tracer_rows_total{tracer=\"b\"} 8"));
    EXPECT_TRUE(has_line(t, "pathfarm_tracer_busy_ratio{tracer=\"b\"} 0"));
    m.observe_frame({true, 40.0, 2, 0, 0, {{"a", 0.5, 12}, {"b", 0.25, 4}}});
    t = m.text();
    EXPECT_TRUE(has_line(t, "pathfarm_tracer_rows_total{tracer=\"b\"} 12"));
}

}  // namespace
}  // namespace pathfarm::coord
