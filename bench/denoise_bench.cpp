// Reconstruction quality along a scripted camera path (issue: real-time reconstruction). The
// coordinator's frame pipeline runs the game (inputs, animation, BVHs) for each frame; the
// frame is rendered at 1 spp with its first hits as a tracer renders it (Embree; any row split
// gives the same bytes); its G-buffer is made as the farm makes it; then the farm's two
// outputs are formed: converging alone (TemporalAccumulator) and the denoiser (temporal).
// Every 10th frame, and the frame after every 20th (for the frame-to-frame change), is
// compared with a converged reference of the same scene state and camera (rendered once at
// `ref_spp` with other random numbers, cached as PFM).
//
// Paths: "game" (builtin:default with its game: the ball rolls, the action key switches the
// lamp and the door, the camera walks and turns), "sponza" (a walk through Sponza), "cesium"
// (an orbit around the skinned, walking Cesium Man).
//
// Prints CSV rows `path,frame,method,relmse,ssim,instability,denoise_ms` (instability: the mean
// absolute frame-to-frame change of the error over the reference's mean, on the frame after a
// pair's first; empty elsewhere) and writes `<out>/denoise_<path>_strip.png` (raw, converging,
// denoised, reference at the strip frame). Arguments: path, scenes folder, cache folder, out
// folder, frames (121), reference spp (512), strip frame (60), the wavelet's kernel radius (1)
// and levels (5), the luminance edge's sigma (8), the temporal anti-aliasing's blend factor
// (DenoiseOptions::taa_alpha; 0: off), extra samples per pixel on average (0) and where they go
// (`targeted`: where history is short, as the farm plans them from the history two frames
// back, coordinator/pacing/extra_samples.h; `dither`: spread evenly) and whether converging
// weighs a pixel by its samples (`weighted`, as the farm does) or counts every frame as one
// (`unweighted`), the far side of silhouettes' weight (EdgeCoverageOptions::model_frames, 3;
// 0: off), the render's divisor (1: 320x180; 2: 160x90, as workload scaling renders smaller than
// the display) and where converging and denoising run then (`display`: on the upscaled render,
// as the farm does; `render`: at the render size, upscaled after).
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <string>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "bench/bench_usage.h"
#include "common/base/folder.h"
#include "common/base/log.h"
#include "common/base/timer.h"
#include "common/film/image_compare.h"
#include "common/film/image_io.h"
#include "common/film/resample.h"
#include "common/scene/load/scene_loader.h"
#include "common/scene/scene_state.h"
#include "coordinator/converge/denoiser.h"
#include "coordinator/frame/frame_pipeline.h"
#include "coordinator/pacing/extra_samples.h"
#include "tracer-node/backend/render_backend.h"

using namespace pathfarm;

namespace {

constexpr int kWidth = 320, kHeight = 180;
constexpr double kFps = 30.0;

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "denoise_bench: %s\n", what.c_str());
    std::exit(1);
}

struct PathSpec {
    std::string scene, game;
    // The input for frame k (absolute camera poses or relative moves, and the action key).
    std::function<coord::PlayerInput(int k)> input;
};

Mat4 look(const Vec3& eye, const Vec3& target) {
    return glm::inverse(glm::lookAt(eye, target, Vec3(0.0f, 1.0f, 0.0f)));
}

PathSpec path_spec(const std::string& path, const std::string& scenes) {
    if (path == "game")
        return {"builtin:default", "default", [](int k) {
                    coord::PlayerInput in;
                    in.move = {0.0f, 0.0f, 0.015f, 0.004f, 0.0f};  // walk forward, turn left
                    in.action = k == 30 || k == 75;                // the lamp and the door
                    return in;
                }};
    if (path == "sponza")
        return {scenes + "/dabrovic-sponza/sponza.obj", "free-camera", [](int k) {
                    coord::PlayerInput in;
                    const Vec3 eye(-10.0f + 0.1f * float(k), 2.0f, 0.8f * std::sin(k / 20.0f));
                    in.camera_to_world = look(eye, eye + Vec3(1.0f, 0.15f, -0.2f));
                    return in;
                }};
    if (path == "cesium")
        return {scenes + "/cesium-man/CesiumMan.gltf", "free-camera", [](int k) {
                    coord::PlayerInput in;
                    const float a = 0.6f + 0.01f * float(k);
                    const Vec3 target(0.0f, 0.75f, 0.0f);
                    in.camera_to_world =
                        look(target + Vec3(2.6f * std::sin(a), 0.4f, 2.6f * std::cos(a)), target);
                    return in;
                }};
    fail("unknown path " + path + " (game, sponza, cesium)");
}

// A render of the scene as of the pipeline's last frame, with its first hits when asked.
struct Shot {
    SceneModel model;
    Camera camera;  // recentred, as the tracers hold it
    std::vector<uint32_t> ids;
};

FloatImage render(tracer::RenderBackend& backend, const Shot& s, uint32_t frame, uint32_t seed,
                  int spp, std::vector<FirstHit>* hits, const std::vector<uint8_t>* extra = nullptr,
                  int width = kWidth, int height = kHeight) {
    FloatImage image(width, height);
    if (hits) hits->assign(std::size_t(width) * height, FirstHit{});
    FrameSpec spec{width, height, frame, seed, spp, 0, s.camera};
    if (extra && !extra->empty()) spec.extra_samples = extra->data();
    const tracer::RenderJob job{spec, IntegratorSettings{},         0, height,
                                {},   hits ? hits->data() : nullptr};
    if (!backend.render_rows(job, image.rgb.data())) fail("render failed");
    if (hits)
        for (FirstHit& h : *hits)
            if (h.hit()) h.instance = s.ids.at(h.instance);  // the scene graph's ids
    return image;
}

// Mean absolute frame-to-frame change of the error, over the reference's mean.
double instability(const FloatImage& out, const FloatImage& out_prev, const FloatImage& ref,
                   const FloatImage& ref_prev) {
    double change = 0.0, mean = 0.0;
    for (std::size_t i = 0; i < out.rgb.size(); ++i) {
        change += std::abs(double(out.rgb[i]) - out_prev.rgb[i] - (ref.rgb[i] - ref_prev.rgb[i]));
        mean += ref.rgb[i];
    }
    return mean > 0.0 ? change / mean : 0.0;
}

void write_strip(const std::string& path, const std::vector<const FloatImage*>& images) {
    FloatImage strip(kWidth * int(images.size()), kHeight);
    for (std::size_t n = 0; n < images.size(); ++n)
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                strip.set_pixel(int(n) * kWidth + x, y, images[n]->pixel(x, y));
    if (Status s = write_image(path, strip); !s) fail(s.error().message);
}

bool is_reference_frame(int k) { return (k % 10 == 0 && k > 0) || (k % 20 == 1 && k > 1); }

struct Args {
    std::string path, cache, out;
    int frames = 121, ref_spp = 512, strip_frame = 60;
    coord::DenoiseOptions denoise;
    double extra = 0.0;
    bool targeted = true;
    bool weigh = true;  // FrameView::sample_weights (as the farm does); false: every frame as one
    int render_divisor = 1;         // render at 320x180 over this, upscaled for display
    bool filter_at_render = false;  // converge and denoise at the render size, then upscale
};

// The cached reference of frame k, or a fresh render of it (written to the cache).
FloatImage reference(const Args& a, tracer::RenderBackend& backend, const Shot& shot, int k) {
    const std::string file =
        a.cache + "/" + a.path + "_" + std::to_string(k) + "_" + std::to_string(a.ref_spp) + ".pfm";
    if (auto cached = read_image(file);
        cached && cached->width == kWidth && cached->height == kHeight)
        return std::move(*cached);
    FloatImage ref = render(backend, shot, uint32_t(k), 99, a.ref_spp, nullptr);
    if (Status s = write_image(file, ref); !s) fail(s.error().message);
    return ref;
}

// The path's frames, each output compared with the reference where there is one.
class PathRun {
public:
    PathRun(const Args& a, const PathSpec& spec, coord::FramePipeline& pipeline,
            tracer::RenderBackend& backend)
        : a_(a), spec_(spec), pipeline_(pipeline), backend_(backend), denoiser_(a.denoise) {}

    void frame(int k) {
        coord::PlayerInput input = spec_.input(k);
        input.sequence = uint64_t(k) + 1;
        const coord::FrameUpdate update = pipeline_.advance(uint64_t(k), k / kFps, {input});
        coord::FrameView view = pipeline_.view(update);
        Shot shot;
        shot.model = to_scene_model(pipeline_.state());
        for (const Instance& inst : shot.model.instances)
            shot.ids.push_back(inst.id);
        shot.camera = recentre_on_camera(shot.model, view.camera);
        if (Status s = backend_.set_scene(shot.model); !s) fail(s.error().message);
        std::vector<FirstHit> hits;
        // Workload scaling's smaller render: converged and denoised at the display size from
        // the upscaled image (the farm's way), or at the render size and upscaled after.
        const int rw = kWidth / a_.render_divisor, rh = kHeight / a_.render_divisor;
        const int fw = a_.filter_at_render ? rw : kWidth, fh = a_.filter_at_render ? rh : kHeight;
        const std::vector<uint8_t> extra = coord::plan_extra_samples(
            a_.targeted ? history_[0] : std::vector<float>{}, rw, rh, a_.extra, uint64_t(k));
        const FloatImage rendered =
            render(backend_, shot, uint32_t(k), 1, 1, &hits, &extra, rw, rh);
        view.gbuffer = coord::gbuffer_from_first_hits(hits, rw, rh, view.camera, fw, fh);
        if (a_.weigh && rw == fw) view.sample_weights = coord::sample_weights(extra, 1);
        const auto to_size = [](const FloatImage& image, int w, int h) {
            return image.width == w && image.height == h ? image : resize_bilinear(image, w, h);
        };
        FloatImage converged = to_size(rendered, fw, fh), denoised = converged;
        accumulator_.blend(converged, view);
        const Timer timer;
        denoiser_.filter(denoised, std::move(view), true);
        const double denoise_ms = timer.milliseconds();
        const FloatImage raw = to_size(rendered, kWidth, kHeight);
        converged = to_size(converged, kWidth, kHeight);
        denoised = to_size(denoised, kWidth, kHeight);
        history_[0] = std::move(history_[1]);  // the farm plans from two frames back
        history_[1] = denoiser_.history_frames();
        const std::map<std::string, const FloatImage*> outputs = {
            {"raw", &raw}, {"converging", &converged}, {"denoised", &denoised}};
        if (is_reference_frame(k)) compare(k, shot, outputs, denoise_ms);
        for (const auto& [method, image] : outputs)
            previous_[method] = *image;
    }

private:
    void compare(int k, const Shot& shot, const std::map<std::string, const FloatImage*>& outputs,
                 double denoise_ms) {
        FloatImage ref = reference(a_, backend_, shot, k);
        for (const auto& [method, image] : outputs) {
            std::string unstable;
            if (k % 20 == 1)
                unstable =
                    std::to_string(instability(*image, previous_.at(method), ref, previous_ref_));
            std::printf("%s,%d,%s,%.6g,%.6f,%s,%.3f\n", a_.path.c_str(), k, method.c_str(),
                        relative_mse(*image, ref), ssim(*image, ref), unstable.c_str(), denoise_ms);
        }
        std::fflush(stdout);
        if (k == a_.strip_frame) {
            for (const auto& [method, image] : outputs)  // linear, for a closer look
                if (Status st =
                        write_image(a_.out + "/denoise_" + a_.path + "_" + method + ".pfm", *image);
                    !st)
                    fail(st.error().message);
        }
        if (k == a_.strip_frame)
            write_strip(
                a_.out + "/denoise_" + a_.path + "_strip.png",
                {outputs.at("raw"), outputs.at("converging"), outputs.at("denoised"), &ref});
        previous_ref_ = std::move(ref);
    }

    const Args& a_;
    const PathSpec& spec_;
    coord::FramePipeline& pipeline_;
    tracer::RenderBackend& backend_;
    coord::TemporalAccumulator accumulator_;
    coord::Denoiser denoiser_;
    std::map<std::string, FloatImage> previous_;  // method -> last frame's output
    std::vector<float> history_[2];               // the denoiser's, two and one frames back
    FloatImage previous_ref_;
};

}  // namespace

int main(int argc, char** argv) {
    if (int code = bench::usage_exit(
            argc, argv, argc >= 5,
            "usage: pathfarm-denoise-bench PATH SCENES CACHE OUT [FRAMES] [REF_SPP] "
            "[STRIP_FRAME] [RADIUS] [LEVELS] [SIGMA_L] [TAA_ALPHA] [EXTRA] [targeted|dither] "
            "[weighted|unweighted] [EDGE_FRAMES]\n"
            "Prints CSV (path, frame, method, relmse, ssim, instability, denoise_ms); "
            "bench/denoise_bench.py runs it.\n");
        code >= 0)
        return code;
    init_logging("denoise-bench", "warn");
    Args a;
    a.path = argv[1];
    a.cache = argv[3];
    a.out = argv[4];
    if (argc > 5) a.frames = std::atoi(argv[5]);
    if (argc > 6) a.ref_spp = std::atoi(argv[6]);
    if (argc > 7) a.strip_frame = std::atoi(argv[7]);
    if (argc > 8) a.denoise.atrous.radius = std::atoi(argv[8]);
    if (argc > 9) a.denoise.atrous.levels = std::atoi(argv[9]);
    if (argc > 10) a.denoise.atrous.sigma_luminance = float(std::atof(argv[10]));
    if (argc > 11) a.denoise.taa_alpha = float(std::atof(argv[11]));
    if (argc > 12) a.extra = std::atof(argv[12]);
    if (argc > 13) a.targeted = std::string(argv[13]) != "dither";
    if (argc > 14) a.weigh = std::string(argv[14]) != "unweighted";
    if (argc > 15) a.denoise.edges.model_frames = float(std::atof(argv[15]));
    if (argc > 16) a.render_divisor = std::max(1, std::atoi(argv[16]));
    if (argc > 17) a.filter_at_render = std::string(argv[17]) == "render";
    const PathSpec spec = path_spec(a.path, argv[2]);
    auto scene = load_scene(spec.scene);
    if (!scene) fail(scene.error().message);
    coord::FramePipeline pipeline(std::move(*scene), {});
    if (Status s = pipeline.start_game(spec.game, spec.scene); !s) fail(s.error().message);
    auto backend = tracer::create_backend(tracer::BackendKind::embree, {0, 0, 0});
    if (!backend) fail(backend.error().message);
    for (const auto& [what, folder] : {std::pair{"CACHE", &a.cache}, std::pair{"OUT", &a.out}})
        if (Status s = create_output_folder(what, *folder); !s) fail(s.error().message);
    std::printf("path,frame,method,relmse,ssim,instability,denoise_ms\n");
    PathRun run(a, spec, pipeline, **backend);
    for (int k = 0; k < a.frames; ++k)
        run.frame(k);
    return 0;
}
