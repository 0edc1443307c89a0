// Writing a posed scene as Wavefront OBJ, so a user can inspect a pose in any tool.
#pragma once

#include <string>

#include "common/base/result.h"
#include "common/scene/scene_model.h"

namespace pathfarm::coord {

// World-space triangles in glTF's coordinate convention: one `o` per node with a mesh, in the
// source file's node-index order (built-in nodes after, in scene order); within it one `v` per
// vertex of each primitive in accessor order, then 1-based `f` lines per triangle. `posed` is
// the output of pose_scene (skinning and morph targets applied).
Status export_posed_obj(const SceneModel& posed, const std::string& path);

}  // namespace pathfarm::coord
