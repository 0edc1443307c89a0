// ChangeSet -> Commit.
#include "coordinator/commit/commit_builder.h"

namespace pathfarm::coord {
namespace {

UpdateVertexRange vertex_range(uint32_t id, const Mesh& mesh, const VertexRange& r) {
    UpdateVertexRange u;
    u.mesh = id;
    u.first = r.first;
    u.positions.assign(mesh.positions.begin() + r.first, mesh.positions.begin() + r.end);
    if (mesh.has_normals())
        u.normals.assign(mesh.normals.begin() + r.first, mesh.normals.begin() + r.end);
    if (mesh.has_tangents())
        u.tangents.assign(mesh.tangents.begin() + r.first, mesh.tangents.begin() + r.end);
    return u;
}

}  // namespace

Commit build_commit(const SceneState& s, const ChangeSet& c, uint64_t frame, uint64_t base_commit) {
    Commit commit;
    commit.frame = frame;
    commit.base_commit = base_commit;
    auto& ops = commit.ops;
    for (uint32_t id : c.images_added)
        if (const auto it = s.images.find(id); it != s.images.end())
            ops.push_back(AddImage{id, it->second});
    for (uint32_t id : c.textures_set)
        if (const auto it = s.textures.find(id); it != s.textures.end())
            ops.push_back(SetTexture{id, it->second});
    for (uint32_t id : c.materials_set)
        if (const auto it = s.materials.find(id); it != s.materials.end())
            ops.push_back(SetMaterial{id, it->second});
    for (uint32_t id : c.instances_removed)
        ops.push_back(RemoveInstance{id});
    for (uint32_t id : c.meshes_removed)
        ops.push_back(RemoveMesh{id});
    for (uint32_t id : c.meshes_added)
        if (const auto it = s.meshes.find(id); it != s.meshes.end())
            ops.push_back(AddMesh{id, it->second});
    for (const auto& [id, range] : c.vertices_changed)
        if (const auto it = s.meshes.find(id); it != s.meshes.end() && range.end > range.first)
            ops.push_back(vertex_range(id, it->second, range));
    for (uint32_t id : c.instances_set)
        if (const auto it = s.instances.find(id); it != s.instances.end())
            ops.push_back(SetInstance{id, it->second});
    for (uint32_t id : c.cameras_set)
        if (const auto it = s.cameras.find(id); it != s.cameras.end())
            ops.push_back(SetCamera{id, it->second, id == s.active_camera});
    if (c.active_camera && !c.cameras_set.count(s.active_camera))
        if (const auto it = s.cameras.find(s.active_camera); it != s.cameras.end())
            ops.push_back(SetCamera{it->first, it->second, true});
    if (c.environment) ops.push_back(SetEnvironment{s.environment});
    if (c.settings) ops.push_back(SetSettings{s.settings});
    for (uint32_t id : c.textures_removed)
        ops.push_back(RemoveTexture{id});
    for (uint32_t id : c.materials_removed)
        ops.push_back(RemoveMaterial{id});
    for (uint32_t id : c.images_removed)
        ops.push_back(RemoveImage{id});
    return commit;
}

}  // namespace pathfarm::coord
