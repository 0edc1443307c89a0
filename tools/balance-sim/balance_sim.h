// The balancing simulation harness: tracers of given speeds with per-frame noise and hiccups
// render cost maps (recorded by the farm or generated) under a balancer from
// coordinator/balance, with a latency per message. Deterministic for a seed.
#pragma once

#include <string>
#include <vector>

#include "common/base/result.h"
#include "coordinator/balance/balancer.h"

namespace pathfarm::sim {

// costs[f][u]: cost of work unit u in frame f, in ms at relative speed 1.
using CostTrace = std::vector<std::vector<double>>;

struct SimOptions {
    std::vector<double> speeds{1.0, 0.6};
    double noise_sigma = 0.05;  // lognormal per tracer and frame
    double hiccup_p = 0.01;     // probability that a tracer takes 2x as long this frame
    double latency_ms = 0.5;    // per message (assignment, tile, re-issue)
    int frames = 128;
    uint64_t seed = 1;
    bool reissue = false;  // idle tracers take not-yet-started units from the slowest
    int units_per_tile = 4;
};

struct FrameResult {
    double frame_ms = 0.0;
    double ideal_ms = 0.0;  // total work / total speed
    double idle_pct = 0.0;  // 100 * sum(t_max - t_i) / (n * t_max); duplicated work counts as idle
};

std::vector<FrameResult> simulate(coord::Balancer& balancer, const SimOptions& options,
                                  const CostTrace& trace);

// frame,unit,cost_us CSV (pathfarm-coordinator --record-costs).
Result<CostTrace> read_cost_trace(const std::string& path);
// A synthetic trace: a bright band that drifts down the image at `speed` units per frame.
CostTrace generate_trace(int units, int frames, double drift_units_per_frame, uint64_t seed);

}  // namespace pathfarm::sim
