// Input-to-frame latency and frame pacing as the player feels them: each input is timed from
// when it was sent to the arrival of the first frame whose echo (last_input_sequence) covers
// it; frame intervals are arrival-to-arrival. Medians and 99th percentiles at exit, every
// frame in a CSV.
#pragma once

#include <chrono>
#include <cstdint>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"

namespace pathfarm::client {

struct LatencySummary {
    std::size_t inputs = 0, frames = 0;
    double latency_p50_ms = 0.0, latency_p99_ms = 0.0;
    double interval_p50_ms = 0.0, interval_p99_ms = 0.0;
};

class LatencyStats {
public:
    using Clock = std::chrono::steady_clock;

    Status open_csv(
        const std::string& path);  // frame,arrival_ms,interval_ms,inputs_acked,latency_ms
    void input_sent(uint64_t sequence, Clock::time_point at);
    void frame_arrived(uint64_t frame, uint64_t last_input_sequence, Clock::time_point at);
    LatencySummary summary() const;

private:
    std::map<uint64_t, Clock::time_point> pending_;  // sent, not yet seen in a frame
    std::vector<double> latencies_ms_, intervals_ms_;
    std::optional<Clock::time_point> first_, last_frame_;
    std::ofstream csv_;
};

// The q-quantile (0..1) of values, by nearest rank; 0 when empty.
double quantile(std::vector<double> values, double q);

}  // namespace pathfarm::client
