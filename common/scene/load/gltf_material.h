// glTF images, textures, samplers and materials, imported before the meshes that use them.
#pragma once

#include <string>

#include "common/scene/scene_model.h"

namespace tinygltf {
class Model;
}

namespace pathfarm {

// Images the loader decoded become scene images; one that was not decoded stays empty, and
// textures pointing at it have no image (they read as their factor alone).
void import_images_and_textures(const tinygltf::Model& gltf, const std::string& path,
                                SceneModel& scene);
// Materials with KHR_materials_{emissive_strength, transmission, ior, specular, volume} and
// KHR_texture_transform on every texture use; only TEXCOORD_0 is read (others warn).
void import_materials(const tinygltf::Model& gltf, const std::string& path, SceneModel& scene);

}  // namespace pathfarm
