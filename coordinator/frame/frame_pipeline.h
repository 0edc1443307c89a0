// Preparing frame N on the coordinator (DESIGN.md, "The frame" steps 1-3): inputs and game
// logic, animation, the acceleration structures, and the commit of what changed, with the BVH
// ops for replicas that traverse the coordinator's BVH. The farm and the offline driver both
// advance their frames through this, so they run one sequence of steps.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/commit/commit.h"
#include "coordinator/accel/accel_updater.h"
#include "coordinator/converge/temporal_accumulator.h"
#include "coordinator/game/game.h"
#include "coordinator/query/ray_query.h"
#include "coordinator/scene_graph/scene_graph.h"

namespace pathfarm::coord {

struct PipelineOptions {
    std::optional<int> clip;      // animation clip to play (default: the scene's first)
    double rebuild_factor = 1.5;  // BVH rebuild when refit SAH exceeds this times a fresh build
};

// What advancing to one frame produced.
struct FrameUpdate {
    uint64_t frame = 0;
    ChangeSet changes;
    std::shared_ptr<const AccelSnapshot> accel;     // this frame's
    std::shared_ptr<const AccelSnapshot> previous;  // the last frame's (null at frame 0)
    uint64_t last_input_sequence = 0;               // the newest input applied so far
    bool unchanged = false;  // nothing in the scene changed since the last frame
    double animate_ms = 0.0, accel_ms = 0.0;
};

class FramePipeline {
public:
    FramePipeline(SceneModel scene, const PipelineOptions& options);

    // The game that takes inputs and drives the scene (coordinator/game); none: animation only.
    Status start_game(const std::string& kind, const std::string& scene_name);
    // Applies `inputs` and advances game, animation and BVHs to `frame` at game time
    // `clock_seconds` (DESIGN.md, "Time": a fixed step per frame).
    FrameUpdate advance(uint64_t frame, double clock_seconds,
                        const std::vector<PlayerInput>& inputs);
    // The commit of `update`'s changes on top of the previous frame's, with or without BVH ops.
    Commit commit(const FrameUpdate& update, bool with_bvh) const;
    // The whole scene as of the last advance (for replicas that join), with or without BVHs.
    Commit snapshot(uint64_t frame, bool with_bvh) const;
    // What converging needs to know of `update` (the G-buffer is the farm's to add).
    FrameView view(const FrameUpdate& update) const;

    SceneGraph& graph() { return graph_; }
    const SceneState& state() const { return graph_.state(); }
    const std::shared_ptr<const AccelSnapshot>& accel() const { return accel_snapshot_; }

private:
    SceneGraph graph_;
    std::unique_ptr<Game> game_;
    RayQueryService queries_;
    AccelUpdater accel_;
    std::shared_ptr<const AccelSnapshot> accel_snapshot_;
    uint64_t last_applied_input_ = 0;
};

}  // namespace pathfarm::coord
