// glTF skins and animations, imported after the node hierarchy (they refer to nodes).
#pragma once

#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/scene/scene_model.h"

namespace tinygltf {
class Model;
}

namespace pathfarm {

// node_map: glTF node index -> SceneModel node index (-1 when the node is not in the scene).
Status import_skins(const tinygltf::Model& gltf, const std::string& path,
                    const std::vector<int>& node_map, SceneModel& scene);
Status import_animations(const tinygltf::Model& gltf, const std::string& path,
                         const std::vector<int>& node_map, SceneModel& scene);

}  // namespace pathfarm
