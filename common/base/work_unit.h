// The protocol's unit of row work (DESIGN.md, "The frame" step 4): frames are split, balanced,
// timed and re-issued in whole units of this many rows (the last unit of a frame may be short).
// Defined once here for the coordinator, the tracers and the simulator.
#pragma once

namespace pathfarm {

inline constexpr int kRowsPerWorkUnit = 4;

}  // namespace pathfarm
