// Applying commits to a replica: validate everything first, then mutate, so a refused commit
// leaves the replica as it was.
#include "common/commit/commit.h"

#include <optional>

#include <fmt/format.h>

#include "common/base/hash.h"
#include "common/base/overloaded.h"

namespace pathfarm {
namespace {

// What vertex updates are checked against: the mesh shapes this commit will meet.
struct MeshShape {
    std::size_t vertices = 0;
    bool normals = false, tangents = false;
};

class ShapeView {
public:
    ShapeView(const SceneState& base, bool ignore_base) : base_(base), ignore_base_(ignore_base) {}
    std::optional<MeshShape> find(uint32_t id) const {
        if (const auto it = overlay_.find(id); it != overlay_.end()) return it->second;
        if (ignore_base_) return std::nullopt;
        const auto it = base_.meshes.find(id);
        if (it == base_.meshes.end()) return std::nullopt;
        return MeshShape{it->second.positions.size(), it->second.has_normals(),
                         it->second.has_tangents()};
    }
    void set(uint32_t id, std::optional<MeshShape> shape) { overlay_[id] = shape; }

private:
    const SceneState& base_;
    bool ignore_base_;
    std::map<uint32_t, std::optional<MeshShape>> overlay_;
};

Status check_op(ShapeView& shapes, const CommitOp& op) {
    return std::visit(
        Overloaded{
            [&](const UpdateVertexRange& u) -> Status {
                const auto shape = shapes.find(u.mesh);
                if (!shape)
                    return make_error(ErrorCode::invalid_argument,
                                      "vertex update of missing mesh {}", u.mesh);
                const std::size_t end = std::size_t(u.first) + u.positions.size();
                if (end > shape->vertices ||
                    (!u.normals.empty() &&
                     (u.normals.size() != u.positions.size() || !shape->normals)) ||
                    (!u.tangents.empty() &&
                     (u.tangents.size() != u.positions.size() || !shape->tangents)))
                    return make_error(ErrorCode::invalid_argument,
                                      "vertex update [{}, {}) does not fit mesh {} ({} vertices)",
                                      u.first, end, u.mesh, shape->vertices);
                return {};
            },
            [&](const AddMesh& a) -> Status {
                for (uint32_t i : a.mesh.indices)
                    if (i >= a.mesh.positions.size())
                        return make_error(ErrorCode::invalid_argument,
                                          "mesh {}: index {} out of range", a.id, i);
                shapes.set(a.id, MeshShape{a.mesh.positions.size(), a.mesh.has_normals(),
                                           a.mesh.has_tangents()});
                return {};
            },
            [&](const RemoveMesh& r) -> Status {
                shapes.set(r.id, std::nullopt);
                return {};
            },
            [&](const SetMeshBvh& b) -> Status {
                if (std::size_t(b.first_node) + b.nodes.size() > b.node_count)
                    return make_error(ErrorCode::invalid_argument,
                                      "mesh {}: BVH nodes [{}, {}) beyond its {} nodes", b.mesh,
                                      b.first_node, b.first_node + b.nodes.size(), b.node_count);
                return {};
            },
            [&](const AddImage& a) -> Status {
                if (a.image.rgba.size() !=
                    std::size_t(a.image.width) * std::size_t(a.image.height) * 4)
                    return make_error(ErrorCode::invalid_argument, "image {}: {} bytes for {}x{}",
                                      a.id, a.image.rgba.size(), a.image.width, a.image.height);
                return {};
            },
            [](const auto&) -> Status { return {}; },
        },
        op);
}

void apply_op(SceneState& s, const CommitOp& op) {
    std::visit(Overloaded{
                   [&](const SetInstance& o) { s.instances[o.id] = o.instance; },
                   [&](const RemoveInstance& o) { s.instances.erase(o.id); },
                   [&](const AddMesh& o) { s.meshes[o.id] = o.mesh; },
                   [&](const RemoveMesh& o) { s.meshes.erase(o.id); },
                   [&](const UpdateVertexRange& o) {
                       Mesh& m = s.meshes.at(o.mesh);
                       // Only what the update carries: a mesh without normals or tangents has no
                       // storage to offset into (begin() + first on an empty vector is undefined).
                       const auto put = [&](const auto& from, auto& to) {
                           if (!from.empty())
                               std::copy(from.begin(), from.end(), to.begin() + o.first);
                       };
                       put(o.positions, m.positions);
                       put(o.normals, m.normals);
                       put(o.tangents, m.tangents);
                   },
                   [&](const SetMaterial& o) { s.materials[o.id] = o.material; },
                   [&](const RemoveMaterial& o) { s.materials.erase(o.id); },
                   [&](const AddImage& o) { s.images[o.id] = o.image; },
                   [&](const RemoveImage& o) { s.images.erase(o.id); },
                   [&](const SetTexture& o) { s.textures[o.id] = o.texture; },
                   [&](const RemoveTexture& o) { s.textures.erase(o.id); },
                   [&](const SetCamera& o) {
                       s.cameras[o.id] = o.camera;
                       if (o.active) s.active_camera = o.id;
                   },
                   [&](const SetEnvironment& o) { s.environment = o.environment; },
                   [&](const SetSettings& o) { s.settings = o.settings; },
                   [](const SetMeshBvh&) {},  // derived data: apply_bvh_op
                   [](const SetTopLevelBvh&) {},
               },
               op);
}

void apply_bvh_op(DerivedBvh& bvh, const CommitOp& op) {
    if (const auto* m = std::get_if<SetMeshBvh>(&op)) {
        BvhData& d = bvh.meshes[m->mesh];
        d.nodes.resize(m->node_count);
        std::copy(m->nodes.begin(), m->nodes.end(), d.nodes.begin() + m->first_node);
        if (!m->prim_indices.empty()) d.prim_indices = m->prim_indices;
    } else if (const auto* t = std::get_if<SetTopLevelBvh>(&op)) {
        bvh.top_instances = t->instance_ids;
        bvh.top = BvhData{t->nodes, t->prim_indices};
    } else if (const auto* r = std::get_if<RemoveMesh>(&op)) {
        bvh.meshes.erase(r->id);
    }
}

}  // namespace

Status apply_commit(ReplicaState& replica, const Commit& commit) {
    if (!commit.is_snapshot && !replica.initialised)
        return make_error(ErrorCode::invalid_argument, "commit {}: replica has no snapshot yet",
                          commit.frame);
    if (!commit.is_snapshot && commit.base_commit != replica.commit)
        return make_error(ErrorCode::invalid_argument,
                          "commit {}: base {} but the replica holds commit {}", commit.frame,
                          commit.base_commit, replica.commit);
    ShapeView shapes(replica.scene, commit.is_snapshot);
    for (const CommitOp& op : commit.ops)
        if (Status st = check_op(shapes, op); !st)
            return make_error(ErrorCode::invalid_argument, "commit {}: {}", commit.frame,
                              st.error().message);
    if (commit.is_snapshot) {
        replica.scene = SceneState{};
        replica.bvh = DerivedBvh{};
    }
    for (const CommitOp& op : commit.ops) {
        apply_op(replica.scene, op);
        apply_bvh_op(replica.bvh, op);
    }
    replica.commit = commit.frame;
    replica.initialised = true;
    return {};
}

uint64_t bvh_hash(const DerivedBvh& bvh) {
    uint64_t h = 0xcbf29ce484222325ULL;
    const auto add = [&](const void* data, std::size_t size) {
        h = fnv1a64(static_cast<const unsigned char*>(data), size, h);
    };
    const auto add_data = [&](const BvhData& d) {
        const uint64_t sizes[2] = {d.nodes.size(), d.prim_indices.size()};
        add(sizes, sizeof(sizes));
        add(d.nodes.data(), d.nodes.size() * sizeof(BvhNode));
        add(d.prim_indices.data(), d.prim_indices.size() * sizeof(uint32_t));
    };
    for (const auto& [id, d] : bvh.meshes) {
        add(&id, sizeof(id));
        add_data(d);
    }
    add(bvh.top_instances.data(), bvh.top_instances.size() * sizeof(uint32_t));
    add_data(bvh.top);
    return h;
}

Commit make_snapshot(const SceneState& s, uint64_t frame) {
    Commit c;
    c.frame = frame;
    c.is_snapshot = true;
    for (const auto& [id, image] : s.images)
        c.ops.push_back(AddImage{id, image});
    for (const auto& [id, texture] : s.textures)
        c.ops.push_back(SetTexture{id, texture});
    for (const auto& [id, material] : s.materials)
        c.ops.push_back(SetMaterial{id, material});
    for (const auto& [id, mesh] : s.meshes)
        c.ops.push_back(AddMesh{id, mesh});
    for (const auto& [id, inst] : s.instances)
        c.ops.push_back(SetInstance{id, inst});
    for (const auto& [id, camera] : s.cameras)
        c.ops.push_back(SetCamera{id, camera, id == s.active_camera});
    c.ops.push_back(SetEnvironment{s.environment});
    c.ops.push_back(SetSettings{s.settings});
    return c;
}

}  // namespace pathfarm
