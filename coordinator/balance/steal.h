// Straggler re-issue inside a frame (docs/balancing.md, "Ours" step 3): a tracer that has
// delivered all it was given takes the tail of the rows the busiest tracer has not rendered
// yet, as much as makes both finish together, and that tracer stops where the tail begins.
// Pure: the farm and the simulator (tools/balance-sim) call this one rule.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "coordinator/balance/row_range.h"

namespace pathfarm::coord {

// A tracer's rows of this frame that the coordinator has not received yet, in row order, and
// what its tiles say about its pace.
struct TracerProgress {
    uint64_t id = 0;
    std::vector<RowRange> missing;
    bool can_take = true;  // false: it cannot render this frame's rows (no replica of it)
    // Milliseconds per row this frame, from its tiles (0: no tile yet: the thief's pace, or
    // slower when no tile came for longer than the thief needs for one, is assumed, and that it
    // is still on its first unit).
    double ms_per_row = 0.0;
    // Time since its last tile (or its assignment) arrived. With a measured pace it has rendered
    // on meanwhile: the rows that time pays for, at the front of `missing`, are done or under
    // way on the tracer. Without one, none are counted.
    double ms_since_news = 0.0;
};

struct Steal {
    uint64_t victim = 0;
    RowRange rows;  // the thief renders these; the victim stops at rows.y0
};

// The steal for `thief`, or nothing. The victim is the tracer with the most work left (its
// missing rows less those it has rendered since its last tile, at its pace); the thief takes
// whole units from the tail of its last gap so that both are predicted to finish together,
// the thief starting `latency_ms` late (the assignment out, its tile back). Nothing is stolen
// while the thief still misses rows of its own, or when the steal would not end the frame at
// least one of the victim's units sooner (a smaller gain is within the estimate's error and
// risks rendering the unit the victim is on twice).
std::optional<Steal> choose_steal(uint64_t thief, const std::vector<TracerProgress>& tracers,
                                  double latency_ms);

}  // namespace pathfarm::coord
