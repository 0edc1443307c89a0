// pathfarm-coordinator command line: the offline frame loop (--offline) and pose export
// (--export-at). The network farm arrives with the farm issue.
#include <cstdio>
#include <numeric>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/base/log.h"
#include "common/scene/load/scene_loader.h"
#include "coordinator/animation/animator.h"
#include "coordinator/animation/skinning.h"
#include "coordinator/export/obj_export.h"
#include "coordinator/offline/offline_driver.h"

namespace {

int fail(const pathfarm::Error& e) {
    std::fprintf(stderr, "pathfarm-coordinator: %s\n", e.message.c_str());
    return e.code == pathfarm::ErrorCode::invalid_argument ? 2 : 1;
}

int export_pose(pathfarm::SceneModel scene, const std::string& clip_name, double at,
                const std::string& path) {
    if (!scene.animations.empty()) {
        auto clip = pathfarm::coord::find_clip(scene, clip_name.empty() ? "0" : clip_name);
        if (!clip) return fail(clip.error());
        pathfarm::coord::apply_clip(scene, *clip, float(at));
    } else if (!clip_name.empty()) {
        return fail({pathfarm::ErrorCode::invalid_argument,
                     "--clip " + clip_name + ": scene has no animations"});
    }
    if (auto s = pathfarm::coord::export_posed_obj(pathfarm::coord::pose_scene(scene), path); !s)
        return fail(s.error());
    spdlog::info("wrote {} (time {} s)", path, at);
    return 0;
}

int offline(pathfarm::SceneModel scene, const std::string& clip_name,
            pathfarm::coord::OfflineOptions o) {
    if (!clip_name.empty()) {
        auto clip = pathfarm::coord::find_clip(scene, clip_name);
        if (!clip) return fail(clip.error());
        o.clip = *clip;
    }
    auto stats = pathfarm::coord::run_offline(std::move(scene), o);
    if (!stats) return fail(stats.error());
    const auto sum = [&](auto field) {
        return std::accumulate(stats->begin() + 1, stats->end(), 0.0,
                               [&](double a, const auto& s) { return a + double(s.*field); });
    };
    const double n = double(std::max<std::size_t>(stats->size() - 1, 1));
    std::printf(
        "frames=%zu snapshot_bytes=%zu commit_bytes_per_frame=%.0f animate_ms=%.3f accel_ms=%.3f "
        "commit_ms=%.3f "
        "replica_ok=1\n",
        stats->size(), stats->front().commit_bytes,
        sum(&pathfarm::coord::OfflineFrameStats::commit_bytes) / n,
        sum(&pathfarm::coord::OfflineFrameStats::animate_ms) / n,
        sum(&pathfarm::coord::OfflineFrameStats::accel_ms) / n,
        sum(&pathfarm::coord::OfflineFrameStats::commit_ms) / n);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::string scene_spec, export_path, clip_name, log_level = "info";
    double export_at = 0.0;
    pathfarm::coord::OfflineOptions o;
    CLI::App app{
        "pathfarm-coordinator: scene graph, animation, BVH maintenance and commit buffers"};
    app.add_option("--scene", scene_spec, "Scene file (.gltf .glb .obj .ply) or builtin:NAME")
        ->required();
    bool offline_mode = false;
    auto* off = app.add_flag("--offline", offline_mode,
                             "Run the frame loop without a network, with an in-process replica");
    app.add_option("--frames", o.frames, "Frames to run (--offline)")->capture_default_str();
    app.add_option("--fps", o.fps, "Game clock: frame f shows time f / fps")->capture_default_str();
    app.add_option(
        "--stats-csv", o.stats_csv,
        "Per-frame CSV: frame,commit_bytes,animate_ms,accel_ms,commit_ms,dynamic_tris,replica_ok");
    app.add_option("--rebuild-factor", o.rebuild_factor,
                   "Rebuild a refitted BVH past this SAH cost ratio")
        ->capture_default_str();
    app.add_flag("--bvh-nodes", o.bvh_nodes,
                 "The replica asks for BVH nodes (as OpenCL tracers will): commits carry changed "
                 "node ranges");
    auto* at = app.add_option("--export-at", export_at,
                              "Export the pose at this time of the clip's own timeline");
    app.add_option("--export", export_path,
                   "OBJ file for --export-at (world-space posed triangles)")
        ->needs(at);
    at->needs("--export");
    app.add_option("--clip", clip_name, "Animation clip by name or index (default: the first)");
    app.add_option("--log-level", log_level, "trace, debug, info, warn or error")
        ->capture_default_str();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    pathfarm::init_logging("pathfarm-coordinator", log_level);
    if (export_path.empty() && off->count() == 0) {
        std::fprintf(stderr,
                     "pathfarm-coordinator: nothing to do (use --offline or --export-at T --export "
                     "FILE.obj)\n");
        return 2;
    }
    auto scene = pathfarm::load_scene(scene_spec);
    if (!scene) return fail(scene.error());
    if (!export_path.empty()) {
        if (const int rc = export_pose(*scene, clip_name, export_at, export_path);
            rc != 0 || off->count() == 0)
            return rc;
    }
    return offline(std::move(*scene), clip_name, o);
}
