// Per-frame BVH maintenance.
#include "coordinator/accel/accel_updater.h"

#include "common/base/timer.h"
#include "common/math/transform.h"

namespace pathfarm::coord {
namespace {

Bounds3f world_box(const Bvh& bvh, const Mat4& m) {
    const Bounds3f b = bvh.bounds();
    Bounds3f out;
    if (b.empty()) return out;
    for (int c = 0; c < 8; ++c)
        out.extend(
            transform_point(m, Vec3(c & 1 ? b.upper.x : b.lower.x, c & 2 ? b.upper.y : b.lower.y,
                                    c & 4 ? b.upper.z : b.lower.z)));
    return out;
}

}  // namespace

std::shared_ptr<const MeshAccel> AccelUpdater::build_mesh(const Mesh& mesh) {
    auto m = std::make_shared<MeshAccel>();
    m->positions = mesh.positions;
    m->indices = mesh.indices;
    m->bvh = build_bvh(m->positions, m->indices);
    m->built_sah = sah_cost(m->bvh);
    ++stats_.builds;
    return m;
}

void AccelUpdater::rebuild_top(AccelSnapshot& snap, const SceneState& state) {
    snap.instances.clear();
    std::vector<Bounds3f> boxes;
    for (const auto& [id, inst] : state.instances) {
        const auto it = snap.meshes.find(inst.mesh);
        if (it == snap.meshes.end() || it->second->bvh.nodes.empty()) continue;
        snap.instances.push_back({id, inst.mesh, inst.transform, glm::inverse(inst.transform)});
        boxes.push_back(world_box(it->second->bvh, inst.transform));
    }
    snap.top = build_bvh(boxes);
    stats_.top_rebuilt = true;
}

std::shared_ptr<const AccelSnapshot> AccelUpdater::build(const SceneState& state, uint64_t frame) {
    const Timer timer;
    stats_ = AccelStats{};
    auto snap = std::make_shared<AccelSnapshot>();
    snap->frame = frame;
    for (const auto& [id, mesh] : state.meshes)
        snap->meshes.emplace(id, build_mesh(mesh));
    rebuild_top(*snap, state);
    stats_.update_ms = timer.milliseconds();
    current_ = snap;
    return current_;
}

std::shared_ptr<const AccelSnapshot> AccelUpdater::update(const SceneState& state,
                                                          const ChangeSet& c, uint64_t frame) {
    if (!current_) return build(state, frame);
    const Timer timer;
    stats_ = AccelStats{};
    auto snap = std::make_shared<AccelSnapshot>(*current_);  // shares every unchanged BVH
    snap->frame = frame;
    bool top_dirty = !c.instances_set.empty() || !c.instances_removed.empty();
    for (uint32_t id : c.meshes_removed)
        top_dirty |= snap->meshes.erase(id) > 0;
    for (uint32_t id : c.meshes_added)
        if (const auto it = state.meshes.find(id); it != state.meshes.end()) {
            snap->meshes[id] = build_mesh(it->second);
            top_dirty = true;
        }
    for (const auto& [id, range] : c.vertices_changed) {
        const auto mesh = state.meshes.find(id);
        const auto old = snap->meshes.find(id);
        if (mesh == state.meshes.end() || old == snap->meshes.end() || c.meshes_added.count(id))
            continue;
        auto m = std::make_shared<MeshAccel>(*old->second);
        std::copy(mesh->second.positions.begin() + range.first,
                  mesh->second.positions.begin() + range.end, m->positions.begin() + range.first);
        refit_bvh(m->bvh, m->positions, m->indices);
        ++stats_.refits;
        if (sah_cost(m->bvh) > rebuild_factor_ * m->built_sah) {
            m->bvh = build_bvh(m->positions, m->indices);
            m->built_sah = sah_cost(m->bvh);
            ++stats_.rebuilds;
        }
        old->second = std::move(m);
        top_dirty = true;  // the mesh's box may have changed
    }
    if (top_dirty) rebuild_top(*snap, state);
    stats_.update_ms = timer.milliseconds();
    current_ = snap;
    return current_;
}

}  // namespace pathfarm::coord
