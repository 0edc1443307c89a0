// The balancing simulation harness: tracers of given speeds with per-frame noise and hiccups
// render cost maps (recorded by the farm or generated) under a balancer from
// coordinator/balance, with a latency per message. Deterministic for a seed.
#pragma once

#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/base/work_unit.h"
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
    int units_per_tile = kUnitsPerTile;  // a tracer sends a tile every this many units
    // Mid-frame stealing follows the balancer (Balancer::steals_mid_frame), as in the farm.
};

struct FrameResult {
    double frame_ms = 0.0;
    double ideal_ms = 0.0;  // total work / total speed
    // 100 * sum(frame - useful_i) / (n * frame): re-rendered rows and waiting count as idle.
    double idle_pct = 0.0;
    // As the farm's stats report it: 100 * sum(max - busy_i) / (n * max) over the tracers'
    // summed tile times (coordinator/balance/unit_costs.h idle_percent).
    double farm_idle_pct = 0.0;
};

std::vector<FrameResult> simulate(coord::Balancer& balancer, const SimOptions& options,
                                  const CostTrace& trace);

// frame,unit,cost_us CSV (pathfarm-coordinator --record-costs).
Result<CostTrace> read_cost_trace(const std::string& path);
// A synthetic trace: a bright band that drifts down the image at `speed` units per frame.
CostTrace generate_trace(int units, int frames, double drift_units_per_frame, uint64_t seed);

}  // namespace pathfarm::sim
