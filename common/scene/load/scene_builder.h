// A small helper for assembling scenes in code (built-in scenes, tests): add materials, meshes
// and nodes, then finish() flattens the hierarchy.
#pragma once

#include "common/scene/scene_model.h"

namespace pathfarm {

class SceneBuilder {
public:
    explicit SceneBuilder(std::string name) { scene_.name = std::move(name); }

    int add_material(Material m);
    int add_mesh(Mesh m);
    int add_image(Image image);
    int add_texture(Texture t);
    // A node with one mesh; parent -1 for a root.
    int add_instance(int mesh, const Mat4& local, int parent = -1, std::string name = {});
    // A root node placed by translation and rotation (TRS), which animation can drive.
    int add_animatable_instance(int mesh, const Vec3& translation, const glm::quat& rotation,
                                std::string name = {});
    // Turns node `node` about `axis` once every `seconds_per_turn` (a clip of its own).
    void add_spin(int node, const Vec3& axis, float seconds_per_turn, std::string clip_name);
    int add_camera(const Camera& camera);
    Environment& environment() { return scene_.environment; }

    SceneModel finish();

private:
    SceneModel scene_;
};

// Convenience constructors for common materials.
Material make_lambert(std::string name, const Rgb& albedo);
Material make_emitter(std::string name, const Rgb& radiance, bool double_sided = false);

}  // namespace pathfarm
