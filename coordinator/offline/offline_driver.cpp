// Offline frame loop.
#include "coordinator/offline/offline_driver.h"

#include <cmath>

#include <spdlog/spdlog.h>

#include "common/base/timer.h"
#include "common/commit/commit_codec.h"
#include "coordinator/commit/bvh_ops.h"
#include "coordinator/frame/farm_stats.h"
#include "coordinator/frame/frame_pipeline.h"

namespace pathfarm::coord {
namespace {

// Sends a commit through the codec into the replica and compares content hashes (and, for a
// replica that holds BVH data, the BVH hash: derived data is checked separately).
bool replicate(ReplicaState& replica, const Commit& commit, const SceneState& truth,
               const AccelSnapshot* bvh_truth, std::size_t& bytes) {
    const EncodedCommit wire = encode_commit(commit);
    bytes = wire.total_bytes();
    auto decoded = decode_commit(wire.commit, wire.chunks);
    if (!decoded) {
        spdlog::error("frame {}: {}", commit.frame, decoded.error().message);
        return false;
    }
    if (Status s = apply_commit(replica, *decoded); !s) {
        spdlog::error("frame {}: {}", commit.frame, s.error().message);
        return false;
    }
    if (bvh_truth && bvh_hash(replica.bvh) != bvh_hash(derived_bvh(*bvh_truth))) {
        spdlog::error("frame {}: replica BVH differs from the coordinator's", commit.frame);
        return false;
    }
    return content_hash(replica.scene) == content_hash(truth);
}

}  // namespace

Result<std::vector<OfflineFrameStats>> run_offline(SceneModel scene, const OfflineOptions& o) {
    if (o.frames <= 0 || !(o.fps > 0.0))
        return make_error(ErrorCode::invalid_argument, "--frames {} / --fps {}: must be positive",
                          o.frames, o.fps);
    if (!std::isfinite(o.fps))  // every frame at time 0
        return make_error(ErrorCode::invalid_argument, "--fps {}: must be finite", o.fps);
    // A NaN factor never rebuilt a degraded BVH (every comparison false), silently.
    if (!(o.rebuild_factor >= 1.0 && std::isfinite(o.rebuild_factor)))
        return make_error(ErrorCode::invalid_argument,
                          "--rebuild-factor {}: must be finite and >= 1", o.rebuild_factor);
    if (o.clip && (*o.clip < 0 || *o.clip >= int(scene.animations.size())))
        return make_error(ErrorCode::invalid_argument, "--clip {}: scene has {} clips", *o.clip,
                          scene.animations.size());
    CsvWriter csv(o.stats_csv, kOfflineStatsColumns);
    if (!csv.good()) return make_error(ErrorCode::io_error, "{}: cannot write", o.stats_csv);
    FramePipeline pipeline(std::move(scene), PipelineOptions{o.clip, o.rebuild_factor});
    ReplicaState replica;
    std::vector<OfflineFrameStats> stats;
    for (int f = 0; f < o.frames; ++f) {
        OfflineFrameStats s;
        s.frame = uint64_t(f);
        // The fixed game clock (DESIGN.md, "Time"); no game and no inputs offline.
        const FrameUpdate update = pipeline.advance(s.frame, double(f) / o.fps, {});
        s.animate_ms = update.animate_ms;
        s.accel_ms = update.accel_ms;
        s.dynamic_tris = pipeline.graph().dynamic_triangles();
        const Timer timer;
        const Commit commit =
            f == 0 ? pipeline.snapshot(s.frame, o.bvh_nodes) : pipeline.commit(update, o.bvh_nodes);
        s.commit_ms = timer.milliseconds();
        s.replica_ok = replicate(replica, commit, pipeline.state(),
                                 o.bvh_nodes ? update.accel.get() : nullptr, s.commit_bytes);
        csv.row(s.frame, s.commit_bytes, s.animate_ms, s.accel_ms, s.commit_ms, s.dynamic_tris,
                s.replica_ok ? 1 : 0);
        stats.push_back(s);
        if (!s.replica_ok)
            return make_error(ErrorCode::backend_error,
                              "frame {}: replica content hash differs from the coordinator's", f);
    }
    return stats;
}

}  // namespace pathfarm::coord
