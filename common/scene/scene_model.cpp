// Queries over the flat scene and flattening of its node hierarchy.
#include "common/scene/scene_model.h"

#include <algorithm>
#include <cmath>

#include "common/base/check.h"
#include "common/math/transform.h"

namespace pathfarm {

const Image* SceneModel::texture_image(const TextureRef& ref) const {
    if (ref.texture < 0 || ref.texture >= int(textures.size())) return nullptr;
    const int image = textures[ref.texture].image;
    return image >= 0 && image < int(images.size()) ? &images[image] : nullptr;
}

void flatten_nodes(SceneModel& scene) {
    std::vector<Mat4> world(scene.nodes.size());
    scene.instances.clear();
    for (std::size_t i = 0; i < scene.nodes.size(); ++i) {
        const Node& node = scene.nodes[i];
        PF_CHECK_LT(node.parent, int(i));
        world[i] = node.parent >= 0 ? world[node.parent] * node.local : node.local;
        for (int mesh : node.meshes)
            scene.instances.push_back({mesh, int(i), world[i]});
        if (node.camera >= 0 && node.camera < int(scene.cameras.size())) {
            // Cameras ignore node scale: keep rotation and translation only.
            Mat4 m = world[i];
            for (int c = 0; c < 3; ++c)
                m[c] = Vec4(glm::normalize(Vec3(m[c])), 0.0f);
            scene.cameras[node.camera].camera_to_world = m;
        }
    }
}

Bounds3f world_bounds(const SceneModel& scene) {
    Bounds3f b;
    for (const Instance& inst : scene.instances)
        for (const Vec3& p : scene.meshes[inst.mesh].positions)
            b.extend(transform_point(inst.transform, p));
    return b;
}

std::size_t triangle_count(const SceneModel& scene) {
    std::size_t n = 0;
    for (const Instance& inst : scene.instances)
        n += scene.meshes[inst.mesh].triangle_count();
    return n;
}

bool has_emissive_triangles(const SceneModel& scene) {
    for (const Instance& inst : scene.instances) {
        const Mesh& mesh = scene.meshes[inst.mesh];
        if (mesh.triangle_count() > 0 && scene.materials[mesh.material].is_emissive()) return true;
    }
    return false;
}

bool has_deformation(const SceneModel& scene) {
    for (const Node& node : scene.nodes)
        for (int m : node.meshes)
            if (node.skin >= 0 || !scene.meshes[m].morph_targets.empty()) return true;
    return false;
}

bool uses_sun_sky(const SceneModel& scene) {
    switch (scene.environment.sky) {
        case SkyMode::on:
            return true;
        case SkyMode::off:
            return false;
        case SkyMode::automatic:
        default:
            return !has_emissive_triangles(scene);
    }
}

double recentre_cell(const Bounds3f& world) {
    constexpr double kCellsAcross = 4.0;
    const double diagonal = world.empty() ? 0.0 : double(glm::length(world.extent()));
    const double cell = std::exp2(std::ceil(std::log2(std::max(diagonal / kCellsAcross, 1e-3))));
    return std::min(cell, 1048576.0);
}

Camera recentre_on_camera(SceneModel& scene, Camera camera) {
    const double cell = recentre_cell(world_bounds(scene));
    const glm::dvec3 eye = glm::dvec3(camera.camera_to_world[3]) + scene.origin;
    const glm::dvec3 origin = glm::floor(eye / cell + 0.5) * cell;
    const glm::dvec3 shift_by = origin - scene.origin;
    scene.origin = origin;
    const auto shift = [&](Mat4& m) { m[3] = Vec4(Vec3(glm::dvec3(m[3]) - shift_by), m[3].w); };
    for (Instance& i : scene.instances)
        shift(i.transform);
    for (Camera& c : scene.cameras)
        shift(c.camera_to_world);
    shift(camera.camera_to_world);
    return camera;
}

}  // namespace pathfarm
