// Loading any scene pathfarm knows: builtin:NAME, glTF 2.0 (.gltf/.glb), Wavefront OBJ + MTL
// (.obj, .obj.gz) and PLY (.ply, .ply.gz). Every loaded scene passes through validation.
#pragma once

#include <string>

#include "common/base/result.h"
#include "common/scene/scene_model.h"

namespace pathfarm {

// spec: "builtin:NAME" or a file path. Errors are one line naming the file and the problem.
Result<SceneModel> load_scene(const std::string& spec);

Result<SceneModel> load_gltf(const std::string& path);
Result<SceneModel> load_obj(const std::string& path);
Result<SceneModel> load_ply(const std::string& path);

}  // namespace pathfarm
