// Commit buffers (DESIGN.md, "The frame" step 3): the typed list of what changed in the
// replicated SceneState since the previous commit. Plain C++; the protobuf form is made only in
// commit_codec.cpp.
#pragma once

#include <cstdint>
#include <variant>
#include <vector>

#include "common/base/result.h"
#include "common/scene/bvh_node.h"
#include "common/scene/scene_state.h"

namespace pathfarm {

struct SetInstance {  // adds or moves an instance
    uint32_t id = 0;
    InstanceState instance;
};
struct RemoveInstance {
    uint32_t id = 0;
};
struct AddMesh {  // adds or replaces a whole mesh (bulk payload)
    uint32_t id = 0;
    Mesh mesh;
};
struct RemoveMesh {
    uint32_t id = 0;
};
// Overwrites vertices [first, first + positions.size()) of a mesh; normals and tangents are
// either empty or the same length.
struct UpdateVertexRange {
    uint32_t mesh = 0;
    uint32_t first = 0;
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;
    std::vector<Vec4> tangents;
};
struct SetMaterial {
    uint32_t id = 0;
    Material material;
};
struct RemoveMaterial {
    uint32_t id = 0;
};
struct AddImage {  // bulk payload
    uint32_t id = 0;
    Image image;
};
struct RemoveImage {
    uint32_t id = 0;
};
struct SetTexture {
    uint32_t id = 0;
    Texture texture;
};
struct RemoveTexture {
    uint32_t id = 0;
};
// The active camera is only ever set through this op, so it always names an existing camera
// once any camera exists.
struct SetCamera {
    uint32_t id = 0;
    Camera camera;
    bool active = false;  // also make it the active camera
};
struct SetEnvironment {
    Environment environment;
};
struct SetSettings {
    RenderSettings settings;
};

// Derived data, only for replicas that asked for the coordinator's BVH (OpenCL tracers):
// nodes [first_node, first_node + nodes.size()) of the mesh's BVH, which has node_count nodes.
// prim_indices is set (whole) when the topology changed: a build or a rebuild.
struct SetMeshBvh {
    uint32_t mesh = 0;
    uint32_t node_count = 0;
    uint32_t first_node = 0;
    std::vector<BvhNode> nodes;
    std::vector<uint32_t> prim_indices;
};
// The whole top level: its primitives are the instances in instance_ids order.
struct SetTopLevelBvh {
    std::vector<uint32_t> instance_ids;
    std::vector<BvhNode> nodes;
    std::vector<uint32_t> prim_indices;
};

using CommitOp =
    std::variant<SetInstance, RemoveInstance, AddMesh, RemoveMesh, UpdateVertexRange, SetMaterial,
                 RemoveMaterial, AddImage, RemoveImage, SetTexture, RemoveTexture, SetCamera,
                 SetEnvironment, SetSettings, SetMeshBvh, SetTopLevelBvh>;

// Commit `frame` applies on top of commit `base_commit`. A snapshot (is_snapshot) replaces the
// whole state and needs no base: it is how a late replica joins.
struct Commit {
    uint64_t frame = 0;
    uint64_t base_commit = 0;
    bool is_snapshot = false;
    std::vector<CommitOp> ops;
};

// BVH data as a replica holds it; derived from the scene, so checked apart from content_hash.
struct BvhData {
    std::vector<BvhNode> nodes;
    std::vector<uint32_t> prim_indices;
};
struct DerivedBvh {
    std::map<uint32_t, BvhData> meshes;  // by mesh id
    std::vector<uint32_t> top_instances;
    BvhData top;
};
uint64_t bvh_hash(const DerivedBvh& bvh);

// A replica of the scene: its state, the BVH data it asked for, and the commit it holds.
struct ReplicaState {
    SceneState scene;
    DerivedBvh bvh;
    uint64_t commit = 0;
    bool initialised = false;  // false until the first snapshot
};

// Applies a commit. Refuses (and leaves the replica untouched) a commit whose base is not the
// replica's commit, a non-snapshot before any snapshot, and ops that refer to missing objects
// or out-of-range vertices.
Status apply_commit(ReplicaState& replica, const Commit& commit);

// A snapshot commit holding the whole state (for replicas that join late).
Commit make_snapshot(const SceneState& state, uint64_t frame);

}  // namespace pathfarm
