// SceneBuilder and material shorthands.
#include "common/scene/load/scene_builder.h"

#include "common/math/transform.h"

namespace pathfarm {

int SceneBuilder::add_material(Material m) {
    scene_.materials.push_back(std::move(m));
    return int(scene_.materials.size()) - 1;
}

int SceneBuilder::add_mesh(Mesh m) {
    scene_.meshes.push_back(std::move(m));
    return int(scene_.meshes.size()) - 1;
}

int SceneBuilder::add_image(Image image) {
    scene_.images.push_back(std::move(image));
    return int(scene_.images.size()) - 1;
}

int SceneBuilder::add_texture(Texture t) {
    scene_.textures.push_back(t);
    return int(scene_.textures.size()) - 1;
}

int SceneBuilder::add_instance(int mesh, const Mat4& local, int parent, std::string name) {
    Node node;
    node.name = std::move(name);
    node.parent = parent;
    node.local = local;
    if (mesh >= 0) node.meshes.push_back(mesh);
    scene_.nodes.push_back(std::move(node));
    return int(scene_.nodes.size()) - 1;
}

int SceneBuilder::add_animatable_instance(int mesh, const Vec3& translation,
                                          const glm::quat& rotation, std::string name) {
    const int node =
        add_instance(mesh, compose_trs(translation, rotation, Vec3(1.0f)), -1, std::move(name));
    Node& n = scene_.nodes[std::size_t(node)];
    n.translation = translation;
    n.rotation = rotation;
    n.has_trs = true;
    return node;
}

void SceneBuilder::add_spin(int node, const Vec3& axis, float seconds_per_turn,
                            std::string clip_name) {
    AnimationSampler s;
    s.components = 4;
    const glm::quat base = scene_.nodes[std::size_t(node)].rotation;
    for (int k = 0; k <= 4; ++k) {  // quarter turns: slerp between keys takes the short way
        s.times.push_back(seconds_per_turn * float(k) / 4.0f);
        const glm::quat q = glm::angleAxis(0.5f * kPi * float(k), glm::normalize(axis)) * base;
        s.values.insert(s.values.end(), {q.x, q.y, q.z, q.w});
    }
    AnimationClip clip;
    clip.name = std::move(clip_name);
    clip.samplers.push_back(std::move(s));
    clip.channels.push_back({node, AnimationPath::rotation, 0});
    clip.start_time = 0.0f;
    clip.end_time = seconds_per_turn;
    scene_.animations.push_back(std::move(clip));
}

int SceneBuilder::add_camera(const Camera& camera) {
    scene_.cameras.push_back(camera);
    const int index = int(scene_.cameras.size()) - 1;
    Node node;
    node.name = camera.name;
    node.local = camera.camera_to_world;
    node.camera = index;
    scene_.nodes.push_back(std::move(node));
    return index;
}

SceneModel SceneBuilder::finish() {
    flatten_nodes(scene_);
    return std::move(scene_);
}

Material make_lambert(std::string name, const Rgb& albedo) {
    Material m;
    m.name = std::move(name);
    m.base_color_factor = Vec4(albedo, 1.0f);
    m.metallic_factor = 0.0f;
    m.roughness_factor = 1.0f;
    m.specular_factor = 0.0f;  // KHR_materials_specular 0: a pure Lambert surface
    return m;
}

Material make_emitter(std::string name, const Rgb& radiance, bool double_sided) {
    Material m = make_lambert(std::move(name), Rgb(0.0f));
    m.emissive_factor = radiance;
    m.double_sided = double_sided;
    return m;
}

}  // namespace pathfarm
