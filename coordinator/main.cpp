// pathfarm-coordinator command line. Today: evaluate and export a scene's pose (--export-at);
// the frame loop and the network arrive with the coordinator-core and farm issues.
#include <cstdio>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/base/log.h"
#include "common/scene/load/scene_loader.h"
#include "coordinator/animation/animator.h"
#include "coordinator/animation/skinning.h"
#include "coordinator/export/obj_export.h"

namespace {

int fail(const pathfarm::Error& e) {
    std::fprintf(stderr, "pathfarm-coordinator: %s\n", e.message.c_str());
    return e.code == pathfarm::ErrorCode::invalid_argument ? 2 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    std::string scene_spec, export_path, clip_name, log_level = "info";
    double export_at = 0.0;
    CLI::App app{"pathfarm-coordinator: scene graph, animation and frame loop of a pathfarm farm"};
    app.add_option("--scene", scene_spec, "Scene file (.gltf .glb .obj .ply) or builtin:NAME")
        ->required();
    auto* at =
        app.add_option("--export-at", export_at,
                       "Evaluate the scene at this time of the clip's own timeline (seconds)");
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
    auto scene = pathfarm::load_scene(scene_spec);
    if (!scene) return fail(scene.error());
    if (export_path.empty()) {
        std::fprintf(stderr,
                     "pathfarm-coordinator: nothing to do (use --export-at T --export FILE.obj)\n");
        return 2;
    }
    if (!scene->animations.empty()) {
        auto clip = pathfarm::coord::find_clip(*scene, clip_name.empty() ? "0" : clip_name);
        if (!clip) return fail(clip.error());
        pathfarm::coord::apply_clip(*scene, *clip, float(export_at));
    } else if (!clip_name.empty()) {
        return fail({pathfarm::ErrorCode::invalid_argument,
                     "--clip " + clip_name + ": scene has no animations"});
    }
    const pathfarm::SceneModel posed = pathfarm::coord::pose_scene(*scene);
    if (auto s = pathfarm::coord::export_posed_obj(posed, export_path); !s) return fail(s.error());
    spdlog::info("wrote {} (time {} s)", export_path, export_at);
    return 0;
}
