// Deformation of skinned and morphed meshes for the current node pose.
#pragma once

#include "common/scene/scene_model.h"

namespace pathfarm::coord {

// World transforms of all nodes (parents precede children in SceneModel::nodes).
std::vector<Mat4> node_world_transforms(const SceneModel& scene);

// Deforms one instance's mesh: morph targets (weighted deltas) first, then linear blend
// skinning with joint matrices world(joint) * inverse_bind and weights normalised to sum 1.
// Skinned results are in world space (glTF ignores the skinned mesh node's own transform);
// morph-only results stay in object space. Positions, normals and tangents are deformed.
Mesh deform_instance(const SceneModel& scene, const Instance& instance,
                     const std::vector<Mat4>& world);

// The scene as it must be rendered for its current pose: every instance of a skinned or
// morphed mesh gets its own deformed mesh (skinned ones with an identity transform) and is
// dynamic (Instance::dynamic), as the coordinator marks it.
// Multithreaded over vertices.
SceneModel pose_scene(const SceneModel& scene);

// Whether an instance's vertices depend on the pose.
bool is_deforming(const SceneModel& scene, const Instance& instance);

}  // namespace pathfarm::coord
