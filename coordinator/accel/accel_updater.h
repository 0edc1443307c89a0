// The acceleration-structure updater (DESIGN.md, "The frame" step 2). Each frame it turns the
// scene state and its ChangeSet into an immutable AccelSnapshot: one bottom-level BVH per mesh
// (static meshes built once; rigid instances only move; deformed meshes refitted and rebuilt
// when their SAH cost exceeds rebuild_factor times a fresh build's) and a top-level BVH over
// the instances, rebuilt whenever an instance or a bottom-level box changed. Snapshots share
// unchanged BVHs and are never modified, so ray queries read the previous frame's snapshot
// while the next one is built.
#pragma once

#include <map>
#include <memory>

#include "common/scene/bvh.h"
#include "common/scene/scene_state.h"
#include "coordinator/scene_graph/change_set.h"

namespace pathfarm::coord {

struct MeshAccel {
    std::vector<Vec3> positions;
    std::vector<uint32_t> indices;
    Bvh bvh;
    double built_sah = 0.0;  // SAH cost right after the last full build
};

struct InstanceAccel {
    uint32_t id = 0;    // instance id in the SceneState
    uint32_t mesh = 0;  // mesh id
    Mat4 to_world{1.0f};
    Mat4 to_object{1.0f};
};

struct AccelSnapshot {
    uint64_t frame = 0;
    std::map<uint32_t, std::shared_ptr<const MeshAccel>> meshes;  // by mesh id
    std::vector<InstanceAccel> instances;                         // the top level's primitives
    Bvh top;
};

struct AccelStats {
    double update_ms = 0.0;
    int builds = 0, refits = 0, rebuilds = 0;
    bool top_rebuilt = false;
};

class AccelUpdater {
public:
    explicit AccelUpdater(double rebuild_factor = 1.5) : rebuild_factor_(rebuild_factor) {}

    // Builds everything from scratch (frame 0, or a replica's snapshot).
    std::shared_ptr<const AccelSnapshot> build(const SceneState& state, uint64_t frame);
    // Applies one frame's changes to the previous snapshot.
    std::shared_ptr<const AccelSnapshot> update(const SceneState& state, const ChangeSet& changes,
                                                uint64_t frame);

    const AccelStats& last_stats() const { return stats_; }
    const std::shared_ptr<const AccelSnapshot>& current() const { return current_; }

private:
    std::shared_ptr<const MeshAccel> build_mesh(const Mesh& mesh);
    void rebuild_top(AccelSnapshot& snap, const SceneState& state);

    double rebuild_factor_;
    std::shared_ptr<const AccelSnapshot> current_;
    AccelStats stats_;
};

}  // namespace pathfarm::coord
