// Straggler re-issue inside a frame (docs/balancing.md, "Ours" step 3): a tracer that has
// delivered all it was given takes the tail half of the last missing gap of the tracer with
// the most rows still missing, and that tracer stops where the tail begins. Pure: the farm
// and the simulator (tools/balance-sim) call this one rule.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "coordinator/balance/row_range.h"

namespace pathfarm::coord {

// A tracer's rows of this frame that the coordinator has not received yet, in row order.
struct TracerProgress {
    uint64_t id = 0;
    std::vector<RowRange> missing;
    bool can_take = true;  // false: it cannot render this frame's rows (no replica of it)
};

struct Steal {
    uint64_t victim = 0;
    RowRange rows;  // the thief renders these; the victim stops at rows.y0
};

// The steal for `thief`, or nothing: when the thief still misses rows of its own, when nobody
// has two units left to give (one is probably being rendered, so less is not worth a message).
std::optional<Steal> choose_steal(uint64_t thief, const std::vector<TracerProgress>& tracers);

}  // namespace pathfarm::coord
