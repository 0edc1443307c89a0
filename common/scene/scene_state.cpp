// Conversion between SceneState and SceneModel.
#include "common/scene/scene_state.h"

#include <algorithm>

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

namespace {

// The dense forms of single objects, shared by the whole conversion and the patch so the two
// cannot differ.
struct DenseIndices {
    std::map<uint32_t, int> images, textures, materials, meshes;
    explicit DenseIndices(const SceneState& s)
        : images(dense_index(s.images)),
          textures(dense_index(s.textures)),
          materials(dense_index(s.materials)),
          meshes(dense_index(s.meshes)) {}
};

Texture dense_texture(const Texture& texture, const DenseIndices& d) {
    Texture out = texture;
    out.image = remap(d.images, texture.image);
    return out;
}

Material dense_material(const Material& material, const DenseIndices& d) {
    Material out = material;
    for (TextureRef* ref : {&out.base_color_texture, &out.metallic_roughness_texture,
                            &out.normal_texture, &out.emissive_texture})
        remap_texture(*ref, d.textures);
    return out;
}

Mesh dense_mesh(const Mesh& mesh, const DenseIndices& d) {
    Mesh out = mesh;
    out.material = std::max(0, remap(d.materials, mesh.material));
    return out;
}

// Instances, cameras (the active one first) and the environment: small, so placed afresh.
void place_view(const SceneState& s, const DenseIndices& d, SceneModel& m) {
    m.instances.clear();
    for (const auto& [id, inst] : s.instances) {
        const int mesh = remap(d.meshes, int(inst.mesh));
        if (mesh >= 0) m.instances.push_back({mesh, -1, inst.transform, id, inst.dynamic});
    }
    m.cameras.clear();
    const auto active = s.cameras.find(s.active_camera);
    if (active != s.cameras.end()) m.cameras.push_back(active->second);
    for (const auto& [id, camera] : s.cameras)
        if (id != s.active_camera) m.cameras.push_back(camera);
    m.environment = s.environment;
    m.origin = glm::dvec3(0.0);
}

// Copies the objects of `ids` from `objects` into `dense` (both in id order), converted.
template <typename T, typename Convert>
void copy_changed(const std::map<uint32_t, T>& objects, const std::set<uint32_t>& ids,
                  std::vector<T>& dense, Convert convert) {
    auto it = objects.begin();
    std::size_t index = 0;
    for (const uint32_t id : ids) {  // both ascending: one walk
        while (it != objects.end() && it->first < id) {
            ++it;
            ++index;
        }
        if (it == objects.end()) return;
        if (it->first == id) dense[index] = convert(it->second);
    }
}

}  // namespace

SceneModel to_scene_model(const SceneState& s) {
    SceneModel m;
    const DenseIndices d(s);
    for (const auto& [id, image] : s.images)
        m.images.push_back(image);
    for (const auto& [id, texture] : s.textures)
        m.textures.push_back(dense_texture(texture, d));
    for (const auto& [id, material] : s.materials)
        m.materials.push_back(dense_material(material, d));
    if (m.materials.empty()) m.materials.emplace_back();
    for (const auto& [id, mesh] : s.meshes)
        m.meshes.push_back(dense_mesh(mesh, d));
    place_view(s, d, m);
    return m;
}

bool patch_scene_model(const SceneState& s, const ChangedObjects& changed, SceneModel& m) {
    const bool same_objects = m.images.size() == s.images.size() &&
                              m.textures.size() == s.textures.size() &&
                              m.materials.size() == std::max<std::size_t>(1, s.materials.size()) &&
                              m.meshes.size() == s.meshes.size() && m.nodes.empty();
    if (!same_objects) {
        m = to_scene_model(s);
        return false;
    }
    const DenseIndices d(s);
    copy_changed(s.images, changed.images, m.images, [](const Image& i) { return i; });
    copy_changed(s.textures, changed.textures, m.textures,
                 [&](const Texture& t) { return dense_texture(t, d); });
    copy_changed(s.materials, changed.materials, m.materials,
                 [&](const Material& x) { return dense_material(x, d); });
    copy_changed(s.meshes, changed.meshes, m.meshes,
                 [&](const Mesh& x) { return dense_mesh(x, d); });
    place_view(s, d, m);
    return true;
}

}  // namespace pathfarm
