// What one frame's tiles reported per 4-row work unit, and what the balancer learns from it
// (docs/balancing.md, "Ours" steps 1 and 2). Pure: the farm and the simulator
// (tools/balance-sim) both reduce their frames with these functions, so they measure one policy.
#pragma once

#include <cstdint>
#include <vector>

#include "coordinator/balance/balancer.h"

namespace pathfarm::coord {

// One work unit of one frame as a tile reported it.
struct UnitReport {
    double rays = 0.0;   // rays traced: a cost that does not depend on the tracer
    double us = 0.0;     // time it took on the tracer that rendered it
    uint64_t owner = 0;  // who delivered it (any nonzero id); 0: nobody yet
};

// Each unit's cost in one tracer-independent scale: its time (which sees what its rays cost
// to shade) times the rays per microsecond of the tracer that rendered it (which removes that
// tracer's speed). A unit of a tracer without timings costs its rays.
std::vector<double> unit_cost_map(const std::vector<UnitReport>& units);

// Rows [0, height) of the units `owner` delivered.
int delivered_rows(const std::vector<UnitReport>& units, uint64_t owner, int height);
// Sum of cost[u] over the units `owner` delivered.
double delivered_cost(const std::vector<UnitReport>& units, const std::vector<double>& cost,
                      uint64_t owner);

// What the balancer hears of a tracer's frame: the range it was first given, the time it
// reported rendering (its own rows and any it took from others), and the cost it delivered.
TracerFrame tracer_feedback(const RowRange& first_range, double render_ms, double cost_delivered);

// Percentage of the tracers' time spent waiting for the slowest: 100 Σ(max − busy) / (n max).
double idle_percent(const std::vector<double>& busy_ms);

}  // namespace pathfarm::coord
