// The denoiser's cost per frame (issue: real-time reconstruction): a 1-spp frame of a scene
// with its first hits (Embree), then the denoiser run repeatedly on it as the farm runs it
// (temporal: accumulation, variance, wavelet; over a still view and under a turning camera) and
// as pathfarm-render --denoise does (one frame alone); and under the turning camera once more,
// each frame after 90 ms of idle cores, as the demo runs it at 10 frames/s (the display stage
// starts while the tracers wait for the next frame: docs/denoise.md). Prints CSV rows
// `scene,width,height,mode,threads,radius,median_ms,p95_ms,runs`. Arguments: scene spec, runs,
// threads (0: all), the wavelet's kernel radius (1: 3x3, 2: 5x5), then width x height pairs.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#include <glm/gtc/matrix_transform.hpp>

#include "bench/bench_usage.h"
#include "common/base/log.h"
#include "common/base/memory.h"
#include "common/base/timer.h"
#include "common/scene/load/scene_loader.h"
#include "common/scene/scene_state.h"
#include "coordinator/converge/denoiser.h"
#include "tracer-node/backend/render_backend.h"

using namespace pathfarm;

namespace {

// A whole decimal number, or a one-line error naming the argument.
int parse_int(const char* what, const char* text, int min) {
    char* end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || v < min || v > 100000) {
        std::fprintf(stderr, "denoise_filter_bench: %s '%s' is not a whole number >= %d\n", what,
                     text, min);
        std::exit(2);
    }
    return int(v);
}

double percentile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size())))];
}

struct Frame {
    FloatImage image;
    coord::FrameView view;
};

// The scene's camera turned by `yaw_degrees` about its own up axis.
Frame render_frame(const SceneModel& loaded, int w, int h, float yaw_degrees) {
    SceneModel scene = loaded;
    Camera camera = scene.cameras.empty() ? frame_bounds(world_bounds(scene), float(w) / float(h))
                                          : scene.cameras.front();
    camera.camera_to_world =
        glm::rotate(camera.camera_to_world, glm::radians(yaw_degrees), Vec3(0.0f, 1.0f, 0.0f));
    camera = recentre_on_camera(scene, camera);
    auto backend = tracer::create_backend(tracer::BackendKind::embree, {0, 0, 0});
    if (!backend || !(*backend)->set_scene(scene)) {
        std::fprintf(stderr, "denoise_filter_bench: no Embree backend for the scene\n");
        std::exit(1);
    }
    Frame f;
    f.image = FloatImage(w, h);
    std::vector<FirstHit> hits(std::size_t(w) * std::size_t(h));
    const tracer::RenderJob job{
        FrameSpec{w, h, 1, 3, 1, 0, camera}, IntegratorSettings{}, 0, h, {}, hits.data()};
    if (!(*backend)->render_rows(job, f.image.rgb.data())) std::exit(1);
    f.view.camera = camera;
    f.view.gbuffer = coord::gbuffer_from_backend_hits(std::move(hits), camera, w, h);
    for (std::size_t i = 0; i < scene.instances.size(); ++i)
        f.view.instances[uint32_t(i + 1)] = scene.instances[i].transform;
    return f;
}

void run(const std::string& spec, const SceneModel& scene, int w, int h, int runs, int threads,
         int radius) {
    // A still view (the same frame again), a turning camera (two views half a degree apart,
    // alternated: every pixel is reprojected) and one frame alone.
    const Frame f = render_frame(scene, w, h, 0.0f), turned = render_frame(scene, w, h, 0.5f);
    std::vector<double> temporal, moving, single, after_idle;
    coord::DenoiseOptions options;
    options.atrous.radius = radius;
    coord::Denoiser still(options), turning(options), turning_after_idle(options);
    for (int r = 0; r < runs; ++r) {
        // The farm hands the denoiser a frame view it owns (moved in): copy it before the clock.
        FloatImage a = f.image, b = f.image;
        coord::FrameView view = f.view;
        const Timer t1;
        still.filter(a, std::move(view), true);
        temporal.push_back(t1.milliseconds());
        const Frame& m = r % 2 ? turned : f;
        FloatImage c = m.image;
        view = m.view;
        const Timer t2;
        turning.filter(c, std::move(view), true);
        moving.push_back(t2.milliseconds());
        const Timer t3;
        coord::denoise_frame(b, f.view.gbuffer, f.view.camera, options);
        single.push_back(t3.milliseconds());
    }
    // Apart from the loop above: the idle slows the next 10 ms or more of any work.
    for (int r = 0; r < runs; ++r) {
        const Frame& m = r % 2 ? turned : f;
        FloatImage d = m.image;
        coord::FrameView view = m.view;
        std::this_thread::sleep_for(std::chrono::milliseconds(90));
        const Timer t4;
        turning_after_idle.filter(d, std::move(view), true);
        after_idle.push_back(t4.milliseconds());
    }
    for (const auto& [mode, ms] :
         {std::pair{"temporal", temporal}, std::pair{"moving", moving}, std::pair{"single", single},
          std::pair{"moving_after_idle", after_idle}})
        std::printf("%s,%d,%d,%s,%d,%d,%.3f,%.3f,%d\n", spec.c_str(), w, h, mode, threads, radius,
                    percentile(ms, 0.5), percentile(ms, 0.95), runs);
}

}  // namespace

int main(int argc, char** argv) {
    if (int code = bench::usage_exit(
            argc, argv, argc >= 6 && (argc - 5) % 2 == 0,
            "usage: pathfarm-denoise-filter-bench SCENE RUNS THREADS RADIUS W H [W H ...]\n"
            "Prints CSV: the denoiser's time per frame alone, for each size.\n");
        code >= 0)
        return code;
    init_logging("denoise-filter-bench", "warn");
    // As the farm's processes do (coordinator/main.cpp): the frames' buffers stay mapped. A
    // single frame in a fresh process (pathfarm-render --denoise) faults its planes in once.
    keep_freed_memory();
    const std::string spec = argv[1];
    const int runs = parse_int("RUNS", argv[2], 1), threads = parse_int("THREADS", argv[3], 0);
    const int radius = parse_int("RADIUS", argv[4], 1) == 2 ? 2 : 1;
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              threads > 0 ? std::size_t(threads) : std::size_t(1) << 16);
    auto scene = load_scene(spec);
    if (!scene) {
        std::fprintf(stderr, "denoise_filter_bench: %s\n", scene.error().message.c_str());
        return 1;
    }
    std::printf("scene,width,height,mode,threads,radius,median_ms,p95_ms,runs\n");
    for (int i = 5; i + 1 < argc; i += 2)
        run(spec, *scene, parse_int("W", argv[i], 8), parse_int("H", argv[i + 1], 8), runs, threads,
            radius);
    return 0;
}
