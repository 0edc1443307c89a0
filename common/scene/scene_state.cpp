// Conversion between SceneState and SceneModel.
#include "common/scene/scene_state.h"

namespace pathfarm {
namespace {

template <typename T>
std::map<uint32_t, int> dense_index(const std::map<uint32_t, T>& objects) {
    std::map<uint32_t, int> index;
    for (const auto& [id, object] : objects)
        index.emplace(id, int(index.size()));
    return index;
}

int remap(const std::map<uint32_t, int>& index, int id) {
    const auto it = index.find(uint32_t(id));
    return id < 0 || it == index.end() ? -1 : it->second;
}

void remap_texture(TextureRef& ref, const std::map<uint32_t, int>& textures) {
    if (ref.texture >= 0) ref.texture = remap(textures, ref.texture);
}

Mesh stripped(const Mesh& m) {
    Mesh out = m;
    out.joints.clear();
    out.weights.clear();
    out.morph_targets.clear();
    out.default_morph_weights.clear();
    return out;
}

}  // namespace

SceneState scene_state_from_model(const SceneModel& model) {
    SceneState s;
    for (std::size_t i = 0; i < model.images.size(); ++i)
        s.images.emplace(uint32_t(i), model.images[i]);
    for (std::size_t i = 0; i < model.textures.size(); ++i)
        s.textures.emplace(uint32_t(i), model.textures[i]);
    for (std::size_t i = 0; i < model.materials.size(); ++i)
        s.materials.emplace(uint32_t(i), model.materials[i]);
    for (std::size_t i = 0; i < model.meshes.size(); ++i)
        s.meshes.emplace(uint32_t(i), stripped(model.meshes[i]));
    for (std::size_t i = 0; i < model.instances.size(); ++i)
        s.instances.emplace(
            uint32_t(i), InstanceState{uint32_t(model.instances[i].mesh),
                                       model.instances[i].transform, model.instances[i].dynamic});
    for (std::size_t i = 0; i < model.cameras.size(); ++i)
        s.cameras.emplace(uint32_t(i), model.cameras[i]);
    s.environment = model.environment;
    return s;
}

SceneModel to_scene_model(const SceneState& s) {
    SceneModel m;
    const auto images = dense_index(s.images), textures = dense_index(s.textures);
    const auto materials = dense_index(s.materials), meshes = dense_index(s.meshes);
    for (const auto& [id, image] : s.images)
        m.images.push_back(image);
    for (const auto& [id, texture] : s.textures) {
        m.textures.push_back(texture);
        m.textures.back().image = remap(images, texture.image);
    }
    for (const auto& [id, material] : s.materials) {
        Material mat = material;
        for (TextureRef* ref : {&mat.base_color_texture, &mat.metallic_roughness_texture,
                                &mat.normal_texture, &mat.emissive_texture})
            remap_texture(*ref, textures);
        m.materials.push_back(std::move(mat));
    }
    if (m.materials.empty()) m.materials.emplace_back();
    for (const auto& [id, mesh] : s.meshes) {
        m.meshes.push_back(mesh);
        m.meshes.back().material = std::max(0, remap(materials, mesh.material));
    }
    for (const auto& [id, inst] : s.instances) {
        const int mesh = remap(meshes, int(inst.mesh));
        if (mesh >= 0) m.instances.push_back({mesh, -1, inst.transform, id, inst.dynamic});
    }
    const auto active = s.cameras.find(s.active_camera);
    if (active != s.cameras.end()) m.cameras.push_back(active->second);
    for (const auto& [id, camera] : s.cameras)
        if (id != s.active_camera) m.cameras.push_back(camera);
    m.environment = s.environment;
    return m;
}

}  // namespace pathfarm
