// The tracer's per-frame scene update (issue: tracer speed, incremental scene updates). For a
// camera walking through Sponza, builtin:default's rolling ball (a shared mesh) and swinging
// door (a mesh placed once), BoxAnimated and the skinned Cesium Man, each frame's scene is
// handed to one Embree backend as a change set (update_scene, what the tracer does now) and to
// another as a whole scene (set_scene, what it did before), alternating which goes first.
// Prints CSV rows `scenario,frames,triangles,update_median_ms,update_p95_ms,rebuild_median_ms,
// rebuild_p95_ms,update_max_ms,ratio` (ratio = rebuild median / update median; the maximum
// shows the frame where the camera crossed into another recentring cell). Arguments: scenes
// folder, frames, log level (debug prints the Embree part of each update), and optionally one
// scenario's name (for a profiler).
#include <algorithm>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "bench/bench_usage.h"
#include "common/base/log.h"
#include "common/base/timer.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/scene_loader.h"
#include "coordinator/animation/animator.h"
#include "coordinator/animation/skinning.h"
#include "tracer-node/backend/render_backend.h"

using namespace pathfarm;

namespace {

using Sequence = std::function<SceneModel(int frame)>;

double percentile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size())))];
}

std::unique_ptr<tracer::RenderBackend> embree() {
    auto b = tracer::create_backend(tracer::BackendKind::embree, tracer::BackendOptions{2, 0, 0});
    if (!b) {
        std::fprintf(stderr, "tracer_update_bench: %s\n", b.error().message.c_str());
        std::exit(1);
    }
    return std::move(b.value());
}

const char* g_only = nullptr;  // the one scenario to run, or all

void run(const char* name, const Sequence& sequence, int frames) {
    if (g_only && std::string(g_only) != name) return;
    auto updated = embree(), rebuilt = embree();
    tracer::SceneStepper steps;
    SceneModel whole;
    std::vector<double> update_ms, rebuild_ms;
    for (int f = 0; f < frames; ++f) {
        const tracer::SceneChanges changes = steps.step(sequence(f));
        const SceneModel& current = steps.scene();
        whole = current;
        const auto timed = [](auto&& call) {
            const Timer t;
            if (Status s = call(); !s) std::fprintf(stderr, "%s\n", s.error().message.c_str());
            return t.milliseconds();
        };
        const auto update = [&] { return updated->update_scene(current, changes); };
        const auto rebuild = [&] { return rebuilt->set_scene(whole); };
        double u = 0.0, r = 0.0;
        if (f % 2) {
            u = timed(update);
            r = timed(rebuild);
        } else {
            r = timed(rebuild);
            u = timed(update);
        }
        if (f > 0) {  // frame 0 builds both
            update_ms.push_back(u);
            rebuild_ms.push_back(r);
        }
    }
    const double um = percentile(update_ms, 0.5), rm = percentile(rebuild_ms, 0.5);
    std::printf("%s,%zu,%zu,%.3f,%.3f,%.3f,%.3f,%.3f,%.1f\n", name, update_ms.size(),
                triangle_count(steps.scene()), um, percentile(update_ms, 0.95), rm,
                percentile(rebuild_ms, 0.95), percentile(update_ms, 1.0), rm / std::max(um, 1e-3));
    std::fflush(stdout);
}

SceneModel load_or_exit(const std::string& path) {
    auto s = load_scene(path);
    if (!s) {
        std::fprintf(stderr, "tracer_update_bench: %s\n", s.error().message.c_str());
        std::exit(1);
    }
    return std::move(s.value());
}

// Moves the instances of `node` (or the first); they are dynamic, as the coordinator's scene
// graph marks an instance that moved (Instance::dynamic).
void move_named(SceneModel& s, const std::string& node, const Mat4& by, bool first_only) {
    for (Instance& inst : s.instances)
        if (inst.node >= 0 && s.nodes[std::size_t(inst.node)].name == node) {
            inst.transform = by * inst.transform;
            inst.dynamic = true;
            if (first_only) return;
        }
}

// Marks the instances that move or deform over `frames` frames of `sequence` dynamic in every
// frame, as the coordinator does from their first move on (before it, the first frames).
Sequence with_dynamic_marked(Sequence sequence, int frames) {
    const SceneModel first = sequence(0);
    std::vector<bool> dynamic(first.instances.size(), false);
    for (int f = 1; f < frames; ++f) {
        const SceneModel s = sequence(f);
        for (std::size_t i = 0; i < dynamic.size(); ++i) {
            const Instance &a = first.instances[i], &b = s.instances[i];
            dynamic[i] = dynamic[i] || a.transform != b.transform ||
                         first.meshes[std::size_t(a.mesh)].positions !=
                             s.meshes[std::size_t(b.mesh)].positions;
        }
    }
    return [sequence, dynamic](int f) {
        SceneModel s = sequence(f);
        for (std::size_t i = 0; i < dynamic.size(); ++i)
            s.instances[i].dynamic = dynamic[i];
        return s;
    };
}

Sequence animated(const SceneModel& base) {
    return [&base](int f) {
        SceneModel s = base;
        coord::apply_clip(s, 0, float(f) / 30.0f);
        if (has_deformation(s)) s = coord::pose_scene(s);
        if (s.cameras.empty()) s.cameras.push_back(frame_bounds(world_bounds(base), 16.0f / 9.0f));
        return s;
    };
}

}  // namespace

int main(int argc, char** argv) {
    if (int code = bench::usage_exit(
            argc, argv, argc <= 5,
            "usage: pathfarm-tracer-update-bench [SCENES_DIR] [FRAMES] [LOG_LEVEL] [SCENARIO]\n"
            "Prints CSV: the tracer's per-frame scene update against a full rebuild. "
            "SCENES_DIR: ../shared/scenes; FRAMES: 40.\n");
        code >= 0)
        return code;
    init_logging("tracer-update-bench", argc > 3 ? argv[3] : "warn");  // debug: Embree's share
    const std::string scenes = argc > 1 ? argv[1] : "../shared/scenes";
    const int frames = argc > 2 ? std::max(4, std::atoi(argv[2])) : 40;
    if (argc > 4) g_only = argv[4];
    std::printf(
        "scenario,frames,triangles,update_median_ms,update_p95_ms,rebuild_median_ms,"
        "rebuild_p95_ms,update_max_ms,ratio\n");
    const SceneModel sponza = load_or_exit(scenes + "/dabrovic-sponza/sponza.obj");
    run(
        "sponza-camera-walk",
        [&](int f) {  // 0.25 m a frame (2.5 m/s at 10 frames/s), crossing a 16 m cell
            SceneModel s = sponza;
            const Vec3 eye(-10.0f + 0.25f * float(f), 2.0f, 0.0f);
            s.cameras = {Camera{}};
            s.cameras[0].camera_to_world = glm::inverse(
                glm::lookAt(eye, eye + Vec3(1.0f, 0.2f, 0.1f * float(f % 7)), Vec3(0, 1, 0)));
            return s;
        },
        frames);
    const SceneModel def = make_default_scene();
    run(
        "default-rolling-ball",
        [&](int f) {
            SceneModel s = def;
            move_named(s, "gold-ball", glm::translate(Mat4(1.0f), Vec3(0.02f * float(f), 0, 0)),
                       true);
            return s;
        },
        frames);
    run(
        "default-swinging-door",
        [&](int f) {
            SceneModel s = def;
            for (Instance& inst : s.instances)
                if (s.nodes[std::size_t(inst.node)].name == "door") {
                    inst.transform = default_scene_door_transform(0.03f * float(f));
                    inst.dynamic = true;
                }
            return s;
        },
        frames);
    const SceneModel box = load_or_exit(scenes + "/box-animated/BoxAnimated.gltf");
    run("box-animated", with_dynamic_marked(animated(box), frames), frames);
    const SceneModel man = load_or_exit(scenes + "/cesium-man/CesiumMan.gltf");
    run("cesium-man-skinned", with_dynamic_marked(animated(man), frames), frames);
    return 0;
}
