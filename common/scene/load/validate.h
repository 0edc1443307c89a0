// Validation of loaded scenes: structural errors are rejected, numeric damage is repaired
// with a warning (DESIGN.md, "Reliability").
#pragma once

#include <string>

#include "common/base/result.h"
#include "common/scene/scene_model.h"

namespace pathfarm {

struct RepairReport {
    std::size_t dropped_nonfinite = 0;    // triangles with a NaN/Inf vertex
    std::size_t dropped_degenerate = 0;   // zero-area triangles
    std::size_t repaired_attributes = 0;  // NaN normals/UVs/tangents zeroed (shading falls back)
};

// Errors: an index out of range, a mesh whose attribute arrays disagree in length, a material
// or texture reference out of range. Repairs: drops NaN/Inf and zero-area triangles, clears
// non-finite attributes, clamps material factors into their valid ranges. Each repair logs
// one warning per mesh naming `source`, the mesh and the count.
Status validate_and_repair(SceneModel& scene, const std::string& source,
                           RepairReport* report = nullptr);

}  // namespace pathfarm
