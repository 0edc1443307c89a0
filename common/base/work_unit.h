// The protocol's unit of row work (DESIGN.md, "The frame" step 4): frames are split, balanced,
// timed and re-issued in whole units of this many rows (the last unit of a frame may be short).
// Defined once here for the coordinator, the tracers and the simulator.
#pragma once

namespace pathfarm {

inline constexpr int kRowsPerWorkUnit = 4;

// A tracer sends a tile at least every this many units of a range (and at the range's end), so
// a tracer not heard of for a while has rendered fewer rows than a tile since.
inline constexpr int kUnitsPerTile = 4;
inline constexpr int kRowsPerTile = kRowsPerWorkUnit * kUnitsPerTile;

}  // namespace pathfarm
