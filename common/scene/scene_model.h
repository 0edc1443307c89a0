// SceneModel: the flat scene shared by coordinator and tracers (STYLE.md §1). Everything is
// addressed by index, which is its stable id within a model. Instances are the flattened
// node hierarchy: one per (node, mesh) pair, with the node's world transform.
#pragma once

#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "common/math/types.h"
#include "common/scene/animation.h"
#include "common/scene/camera.h"
#include "common/scene/environment.h"
#include "common/scene/material.h"
#include "common/scene/mesh.h"
#include "common/scene/texture.h"

namespace pathfarm {

struct Node {
    std::string name;
    int parent = -1;
    Mat4 local{1.0f};  // equals compose_trs(translation, rotation, scale) when has_trs
    // glTF TRS, which animation overrides component by component. A node given as a matrix
    // has has_trs = false and cannot be animated (glTF forbids animating it).
    Vec3 translation{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
    Vec3 scale{1.0f};
    bool has_trs = false;
    std::vector<int> meshes;
    int camera = -1;
    int skin = -1;                     // index into SceneModel::skins
    std::vector<float> morph_weights;  // node.weights, or the mesh's default weights
    int source_index = -1;             // the node's index in its glTF file; -1 if none
};

struct Instance {
    int mesh = -1;
    int node = -1;
    Mat4 transform{1.0f};  // object to world
    uint32_t id = 0;       // the scene graph's id in a replica's model (first hits); 0 if loaded
    // Moves or deforms from frame to frame (the coordinator's scene graph says so): tracers keep
    // it out of the BVH they bake static meshes into, so moving it costs a top-level commit.
    bool dynamic = false;
};

struct SceneModel {
    std::string name;
    std::vector<Image> images;
    std::vector<Texture> textures;
    std::vector<Material> materials;
    std::vector<Mesh> meshes;
    std::vector<Node> nodes;  // parents precede children
    std::vector<Instance> instances;
    std::vector<Camera> cameras;  // camera_to_world already in world space
    std::vector<Skin> skins;
    std::vector<AnimationClip> animations;
    Environment environment;
    // The world position of this model's origin: zero as loaded, moved by recentre_on_camera.
    glm::dvec3 origin{0.0};

    const Image* texture_image(const TextureRef& ref) const;
};

// Recomputes world transforms of nodes (parents first) and rebuilds instances and camera
// transforms from them (a node's camera index points into `cameras`).
void flatten_nodes(SceneModel& scene);

Bounds3f world_bounds(const SceneModel& scene);

// Camera-relative rendering: moves the world so that the origin is near `camera`'s eye,
// subtracting in double precision from every instance and camera translation. Far from the
// world origin, float hit points and ray offsets lose precision (at 1e4 m one float step is
// 1 mm: light leaks and acne); near the camera, where the pixels are, they keep it. Geometry
// whose vertices themselves hold large coordinates keeps the precision it was stored with.
// The new origin is the eye snapped to a grid of cells about a quarter of the scene's size
// (recentre_cell), so a camera moving within its cell leaves every instance where it was
// (backends have no acceleration structure to update), and the result depends on this frame
// only, never on earlier ones (a tracer that joins late renders the same bits). Sets
// scene.origin; returns `camera` moved likewise.
Camera recentre_on_camera(SceneModel& scene, Camera camera);
// The cell edge: the power of two nearest above a quarter of the world bounds' diagonal.
double recentre_cell(const Bounds3f& world);
std::size_t triangle_count(const SceneModel& scene);
bool has_emissive_triangles(const SceneModel& scene);
// Whether the sun/sky lights this scene (Environment::sky resolved against its emitters).
bool uses_sun_sky(const SceneModel& scene);
// Whether any mesh is skinned or has morph targets (its vertices depend on the pose).
bool has_deformation(const SceneModel& scene);

}  // namespace pathfarm
