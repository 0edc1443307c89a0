// Offline frame loop.
#include "coordinator/offline/offline_driver.h"

#include <fstream>

#include <spdlog/spdlog.h>

#include "common/base/timer.h"
#include "common/commit/commit_codec.h"
#include "coordinator/accel/accel_updater.h"
#include "coordinator/commit/bvh_ops.h"
#include "coordinator/commit/commit_builder.h"
#include "coordinator/query/ray_query.h"
#include "coordinator/scene_graph/scene_graph.h"

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

class CsvWriter {
public:
    explicit CsvWriter(const std::string& path) {
        if (path.empty()) return;
        out_.open(path);
        out_ << "frame,commit_bytes,animate_ms,accel_ms,commit_ms,dynamic_tris,replica_ok\n";
    }
    bool ok() const { return !out_.is_open() || out_.good(); }
    void row(const OfflineFrameStats& s) {
        if (!out_.is_open()) return;
        out_ << s.frame << ',' << s.commit_bytes << ',' << s.animate_ms << ',' << s.accel_ms << ','
             << s.commit_ms << ',' << s.dynamic_tris << ',' << (s.replica_ok ? 1 : 0) << '\n';
        out_.flush();
    }

private:
    std::ofstream out_;
};

}  // namespace

Result<std::vector<OfflineFrameStats>> run_offline(SceneModel scene, const OfflineOptions& o) {
    if (o.frames <= 0 || !(o.fps > 0.0))
        return make_error(ErrorCode::invalid_argument, "--frames {} / --fps {}: must be positive",
                          o.frames, o.fps);
    if (o.clip && (*o.clip < 0 || *o.clip >= int(scene.animations.size())))
        return make_error(ErrorCode::invalid_argument, "--clip {}: scene has {} clips", *o.clip,
                          scene.animations.size());
    CsvWriter csv(o.stats_csv);
    if (!csv.ok()) return make_error(ErrorCode::io_error, "{}: cannot write", o.stats_csv);
    SceneGraph graph(std::move(scene));
    if (o.clip) graph.set_playing_clip(*o.clip);
    AccelUpdater accel(o.rebuild_factor);
    RayQueryService queries;
    ReplicaState replica;
    std::vector<OfflineFrameStats> stats;
    for (int f = 0; f < o.frames; ++f) {
        OfflineFrameStats s;
        s.frame = uint64_t(f);
        Timer timer;
        graph.advance(double(f) / o.fps);  // the fixed game clock (DESIGN.md, "Time")
        s.animate_ms = timer.milliseconds();
        s.dynamic_tris = graph.dynamic_triangles();
        const ChangeSet changes = graph.take_changes();
        timer.reset();
        const auto previous = accel.current();
        const auto snapshot = f == 0 ? accel.build(graph.state(), s.frame)
                                     : accel.update(graph.state(), changes, s.frame);
        queries.publish(snapshot);
        s.accel_ms = timer.milliseconds();
        timer.reset();
        Commit commit = f == 0 ? make_snapshot(graph.state(), s.frame)
                               : build_commit(graph.state(), changes, s.frame, s.frame - 1);
        if (o.bvh_nodes)
            for (CommitOp& op : build_bvh_ops(f == 0 ? nullptr : previous.get(), *snapshot))
                commit.ops.push_back(std::move(op));
        s.commit_ms = timer.milliseconds();
        s.replica_ok = replicate(replica, commit, graph.state(),
                                 o.bvh_nodes ? snapshot.get() : nullptr, s.commit_bytes);
        csv.row(s);
        stats.push_back(s);
        if (!s.replica_ok)
            return make_error(ErrorCode::backend_error,
                              "frame {}: replica content hash differs from the coordinator's", f);
    }
    return stats;
}

}  // namespace pathfarm::coord
