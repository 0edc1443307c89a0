// Replica bookkeeping: commits in, the scene and its change set out.
#include "tracer-node/replica/replica.h"

#include "common/base/overloaded.h"

namespace pathfarm::tracer {
namespace {

template <typename T>
std::map<uint32_t, uint32_t> dense_index(const std::map<uint32_t, T>& objects) {
    std::map<uint32_t, uint32_t> index;
    for (const auto& [id, object] : objects)
        index.emplace(id, uint32_t(index.size()));
    return index;
}

// Instance id -> index in to_scene_model's order (instances of missing meshes are skipped).
std::map<uint32_t, uint32_t> instance_index(const SceneState& s) {
    std::map<uint32_t, uint32_t> index;
    for (const auto& [id, inst] : s.instances)
        if (s.meshes.count(inst.mesh)) index.emplace(id, uint32_t(index.size()));
    return index;
}

std::vector<uint32_t> indices_of(const std::set<uint32_t>& ids,
                                 const std::map<uint32_t, uint32_t>& index) {
    std::vector<uint32_t> out;
    for (uint32_t id : ids)
        if (const auto it = index.find(id); it != index.end()) out.push_back(it->second);
    return out;
}

bool emissive_mesh(const SceneState& s, uint32_t mesh) {
    const auto m = s.meshes.find(mesh);
    if (m == s.meshes.end()) return false;
    const auto mat = s.materials.find(uint32_t(m->second.material));
    return mat != s.materials.end() && mat->second.is_emissive();
}

}  // namespace

bool Replica::PendingChanges::empty() const {
    return !structure && !camera && !settings && !environment && !lights && instances.empty() &&
           meshes.empty() && materials.empty() && textures.empty() && images.empty();
}

void Replica::add_chunk(uint64_t frame, std::shared_ptr<const ParsedChunk> chunk) {
    chunks_[frame].push_back(std::move(chunk));
}

Status Replica::apply(const ParsedCommit& parsed, uint64_t frame) {
    auto chunks = std::move(chunks_[frame]);
    chunks_.erase(chunks_.begin(), chunks_.upper_bound(frame));  // older leftovers are stale
    auto commit = decode_commit(parsed, chunks);
    if (!commit) return commit.error();
    return apply(*commit);
}

Status Replica::apply(const Commit& commit) {
    const PendingChanges before = pending_;
    if (commit.is_snapshot) pending_.structure = pending_.camera = pending_.lights = true;
    for (const CommitOp& op : commit.ops)
        note(op);
    if (Status s = apply_commit(state_, commit); !s) {
        pending_ = before;
        return s;
    }
    return {};
}

// Classifies one op against the state it is about to change.
void Replica::note(const CommitOp& op) {
    const SceneState& s = state_.scene;
    PendingChanges& p = pending_;
    std::visit(
        Overloaded{
            [&](const SetInstance& o) {
                const auto it = s.instances.find(o.id);
                // Becoming dynamic moves an instance out of the baked BVH: a new layout.
                if (it == s.instances.end() || it->second.mesh != o.instance.mesh ||
                    it->second.dynamic != o.instance.dynamic)
                    p.structure = true;
                else
                    p.instances.insert(o.id);
            },
            [&](const UpdateVertexRange& o) { p.meshes.insert(o.mesh); },
            [&](const SetMaterial& o) {
                const auto it = s.materials.find(o.id);
                if (it == s.materials.end()) return void(p.structure = true);
                p.materials.insert(o.id);
                p.lights = p.lights || it->second.is_emissive() || o.material.is_emissive();
            },
            [&](const AddImage& o) {
                if (s.images.count(o.id))
                    p.images.insert(o.id);
                else
                    p.structure = true;
            },
            [&](const SetTexture& o) {
                if (s.textures.count(o.id))
                    p.textures.insert(o.id);
                else
                    p.structure = true;
            },
            [&](const SetCamera& o) { p.camera = p.camera || o.active || o.id == s.active_camera; },
            [&](const SetEnvironment&) { p.environment = p.lights = true; },
            [&](const SetSettings&) { p.settings = true; },
            [&](const SetMeshBvh&) {},                 // derived data (provide_mesh_bvhs)
            [&](const SetTopLevelBvh&) {},             // likewise
            [&](const auto&) { p.structure = true; },  // adds and removes
        },
        op);
}

SceneChanges Replica::update_scene(SceneModel& scene) {
    const SceneState& s = state_.scene;
    const PendingChanges& p = pending_;
    SceneChanges c;
    c.structure = p.structure;
    c.camera = p.camera;
    c.settings = p.settings;
    c.environment = p.environment;
    c.lights = p.lights;
    if (c.structure) {
        scene = to_scene_model(s);
    } else {
        c.instances = indices_of(p.instances, instance_index(s));
        c.mesh_vertices = indices_of(p.meshes, dense_index(s.meshes));
        c.materials = indices_of(p.materials, dense_index(s.materials));
        std::set<uint32_t> textures = p.textures;
        for (const auto& [id, t] : s.textures)  // a texture whose image changed changed
            if (p.images.count(uint32_t(t.image))) textures.insert(id);
        c.textures = indices_of(textures, dense_index(s.textures));
        for (uint32_t id : p.instances)
            c.lights = c.lights || emissive_mesh(s, s.instances.at(id).mesh);
        for (uint32_t mesh : p.meshes)
            c.lights = c.lights || emissive_mesh(s, mesh);
        // A model that does not hold this state's objects (the first call) is converted
        // whole, which every backend must then take as new.
        if (!patch_scene_model(s, {p.images, p.textures, p.materials, p.meshes}, scene))
            c = SceneChanges::everything();
    }
    pending_ = PendingChanges{};
    return c;
}

}  // namespace pathfarm::tracer
