// The coordinator's frame loop without a network: animation, acceleration-structure updates,
// commit building, and an in-process replica that applies every commit (through the wire
// codec) and checks its content hash against the coordinator's.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/scene/scene_model.h"

namespace pathfarm::coord {

struct OfflineOptions {
    int frames = 60;
    double fps = 30.0;
    std::optional<int> clip;      // default: the scene's first clip, if any
    std::string stats_csv;        // one row per frame; empty: none
    double rebuild_factor = 1.5;  // BVH rebuild when refit SAH exceeds this times a fresh build
    bool bvh_nodes = false;       // the replica asked for BVH nodes (as OpenCL tracers do)
};

struct OfflineFrameStats {
    uint64_t frame = 0;
    std::size_t commit_bytes = 0;
    double animate_ms = 0.0, accel_ms = 0.0, commit_ms = 0.0;
    std::size_t dynamic_tris = 0;
    bool replica_ok = false;
};

// Runs the loop; fails on the first replica mismatch only after writing its stats row.
Result<std::vector<OfflineFrameStats>> run_offline(SceneModel scene, const OfflineOptions& options);

}  // namespace pathfarm::coord
