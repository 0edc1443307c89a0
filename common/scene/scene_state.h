// SceneState: the replicated scene (DESIGN.md, "Replica equality"). Every object has a stable
// id that commits refer to; references between objects are ids too (a mesh's material, a
// material's textures, a texture's image, an instance's mesh). to_scene_model() turns it into
// the dense SceneModel the renderers read.
#pragma once

#include <cstdint>
#include <map>
#include <set>

#include "common/scene/scene_model.h"

namespace pathfarm {

struct InstanceState {
    uint32_t mesh = 0;  // mesh id
    Mat4 transform{1.0f};
    bool dynamic = false;  // Instance::dynamic
};

// Per-frame render settings that travel with the scene.
struct RenderSettings {
    int width = 640;
    int height = 360;
    int spp = 1;
    int max_depth = 8;
    uint32_t seed = 0;
};

struct SceneState {
    std::map<uint32_t, Image> images;
    std::map<uint32_t, Texture> textures;    // Texture::image is an image id
    std::map<uint32_t, Material> materials;  // TextureRef::texture is a texture id
    std::map<uint32_t, Mesh> meshes;         // Mesh::material is a material id
    std::map<uint32_t, InstanceState> instances;
    std::map<uint32_t, Camera> cameras;
    uint32_t active_camera = 0;
    Environment environment;
    RenderSettings settings;
};

// Ids are the SceneModel's indices; instances keep their order. Skinning data stays behind:
// the replicated meshes are already deformed.
SceneState scene_state_from_model(const SceneModel& model);
// Dense copy for rendering: ids map to indices in id order; dangling references become -1
// (or the first material).
SceneModel to_scene_model(const SceneState& state);

// Ids of objects whose content changed while no object was added or removed.
struct ChangedObjects {
    std::set<uint32_t> images, textures, materials, meshes;
};
// Brings `model`, made by to_scene_model() (or this) from an earlier state holding the same
// objects, to `state` without copying what did not change: the named objects are converted
// again, instances and cameras placed afresh (a matrix each) and the origin reset, so the
// result equals to_scene_model(state). A tracer's per-frame copy of a textured scene was
// megabytes (docs/performance.md). Converts the whole state, and returns false, when the
// model does not hold the same objects.
bool patch_scene_model(const SceneState& state, const ChangedObjects& changed, SceneModel& model);

// 64-bit content hash over everything in the state, in id order, floats by bit pattern.
uint64_t content_hash(const SceneState& state);

}  // namespace pathfarm
