// Loads the scene, renders it with the chosen backend (in passes, for progress and time
// budgets) and writes the image.
#include "tools/render/render_tool.h"

#include <cmath>
#include <optional>
#include <utility>

#include <spdlog/spdlog.h>

#include "common/base/timer.h"
#include "common/film/film.h"
#include "common/film/image_compare.h"
#include "common/film/image_io.h"
#include "common/math/transform.h"
#include "common/scene/load/scene_loader.h"
#include "coordinator/animation/animator.h"
#include "coordinator/animation/skinning.h"
#include "coordinator/converge/denoiser.h"
#include "tracer-node/backend/render_backend.h"

namespace pathfarm::tools {
namespace {

Result<Camera> pick_camera(const SceneModel& scene, const RenderToolOptions& o, float aspect) {
    if (o.look_from) {
        if (!o.look_at || *o.look_from == *o.look_at ||
            !(o.fov_degrees > 0.0f && o.fov_degrees < 180.0f))
            return make_error(ErrorCode::invalid_argument,
                              "--look-from needs --look-at at another point and --fov in (0, 180)");
        if (!orients_view(*o.look_at - *o.look_from, o.up))
            return make_error(ErrorCode::invalid_argument,
                              "--up {} {} {}: zero or parallel to the view from --look-from to "
                              "--look-at (the image would have no up)",
                              o.up.x, o.up.y, o.up.z);
        Camera c;
        c.name = "command-line";
        c.yfov_radians = glm::radians(o.fov_degrees);
        c.camera_to_world = look_at_camera(*o.look_from, *o.look_at, o.up);
        return c;
    }
    const int index = o.camera;
    if (index < -1)  // was taken as -1, silently
        return make_error(ErrorCode::invalid_argument,
                          "--camera {}: must be -1 (the first camera or a framing) or an index",
                          index);
    if (index >= int(scene.cameras.size()))
        return make_error(ErrorCode::invalid_argument, "--camera {}: scene has {} camera(s)", index,
                          scene.cameras.size());
    if (index >= 0) return scene.cameras[index];
    if (!scene.cameras.empty()) return scene.cameras[0];
    return frame_bounds(world_bounds(scene), aspect);
}

Status check_options(const RenderToolOptions& o) {
    if (o.width <= 0 || o.height <= 0 || o.width > 16384 || o.height > 16384)
        return make_error(ErrorCode::invalid_argument, "--width/--height {}x{}: must be 1..16384",
                          o.width, o.height);
    if (o.spp <= 0 && !o.seconds)
        return make_error(ErrorCode::invalid_argument, "--spp {}: must be positive", o.spp);
    if (o.max_depth < 0 || o.max_depth > 1024)
        return make_error(ErrorCode::invalid_argument, "--max-depth {}: must be 0..1024",
                          o.max_depth);
    // Written as !(x > 0) so that NaN is refused too; infinite seconds would never finish.
    if (o.seconds && !(*o.seconds > 0.0 && std::isfinite(*o.seconds)))
        return make_error(ErrorCode::invalid_argument, "--seconds {}: must be positive and finite",
                          *o.seconds);
    // A NaN time posed the clip somewhere and a NaN or negative exposure wrote a black PNG,
    // both silently; a NaN point made the camera check blame --up.
    if (o.time && !std::isfinite(*o.time))
        return make_error(ErrorCode::invalid_argument, "--time {}: must be finite", *o.time);
    if (!(o.exposure > 0.0f && std::isfinite(o.exposure)))
        return make_error(ErrorCode::invalid_argument, "--exposure {}: must be positive and finite",
                          o.exposure);
    for (const auto& [flag, point] :
         {std::pair{"--look-from", o.look_from}, std::pair{"--look-at", o.look_at},
          std::pair{"--up", std::optional<Vec3>(o.up)}})
        if (point && !is_finite(*point))
            return make_error(ErrorCode::invalid_argument, "{} {} {} {}: must be finite", flag,
                              point->x, point->y, point->z);
    return check_image_format(o.out);
}

// Applies --time/--clip, then skinning and morph targets (at the rest pose without --time).
Status pose(SceneModel& scene, const RenderToolOptions& o) {
    if (o.time && !scene.animations.empty()) {
        auto clip = coord::find_clip(scene, o.clip.empty() ? "0" : o.clip);
        if (!clip) return clip.error();
        coord::apply_clip(scene, *clip, float(*o.time));
    } else if (!o.clip.empty() && scene.animations.empty()) {
        return make_error(ErrorCode::invalid_argument, "--clip {}: scene has no animations",
                          o.clip);
    }
    if (has_deformation(scene)) scene = coord::pose_scene(scene);
    return {};
}

constexpr int kProgressBandRows = 32;

// Adds a pass of `pass_spp` samples into the running mean of `done` samples.
void accumulate(FloatImage& mean, const FloatImage& pass, int done, int pass_spp) {
    const double w = double(pass_spp) / double(done + pass_spp);
    for (std::size_t i = 0; i < mean.rgb.size(); ++i)
        mean.rgb[i] = float(double(mean.rgb[i]) + (double(pass.rgb[i]) - mean.rgb[i]) * w);
}

// Loads the scene and poses it (pose above).
Result<SceneModel> load_posed_scene(const RenderToolOptions& o) {
    const Timer load_timer;
    auto scene = load_scene(o.scene);
    if (!scene) return scene.error();
    spdlog::info("{}: {} triangles, {} instances, {} materials, {} textures (loaded in {:.2f} s)",
                 o.scene, triangle_count(*scene), scene->instances.size(), scene->materials.size(),
                 scene->textures.size(), load_timer.seconds());
    if (Status s = pose(*scene, o); !s) return s.error();
    const Bounds3f bounds = world_bounds(*scene);
    spdlog::debug("{}: bounds ({:.3g}, {:.3g}, {:.3g}) to ({:.3g}, {:.3g}, {:.3g})", o.scene,
                  bounds.lower.x, bounds.lower.y, bounds.lower.z, bounds.upper.x, bounds.upper.y,
                  bounds.upper.z);
    return scene;
}

class ProgressLog {
public:
    // At most one line every two seconds.
    void operator()(const std::string& what) {
        if (timer_.seconds() - last_ < 2.0) return;
        last_ = timer_.seconds();
        spdlog::info("progress: {} in {:.1f} s", what, last_);
    }

private:
    Timer timer_;
    double last_ = 0.0;
};

// Time budget: passes that double in size; sample indices continue across passes.
// `hits` (null or one per pixel) takes the first pass's first hits.
Status render_for_seconds(tracer::RenderBackend& backend, tracer::RenderJob job, double seconds,
                          FloatImage& image, RenderSummary& summary, SampleCounters& counters,
                          FirstHit* hits) {
    FloatImage pass(image.width, image.height);
    ProgressLog progress;
    const Timer timer;
    for (int pass_spp = 1; timer.seconds() < seconds; pass_spp *= 2) {
        job.frame.first_sample = summary.spp;
        job.frame.spp = pass_spp;
        job.first_hits = summary.spp == 0 ? hits : nullptr;
        auto stats = backend.render_rows(job, pass.rgb.data());
        if (!stats) return stats.error();
        accumulate(image, pass, summary.spp, job.frame.spp);
        summary.spp += job.frame.spp;
        counters.add(stats->counters);
        progress(fmt::format("{} spp", summary.spp));
    }
    return {};
}

// Fixed spp: all samples of a band of rows at once, so the image is bit for bit the one any
// farm split renders (docs/determinism.md).
Status render_spp(tracer::RenderBackend& backend, tracer::RenderJob job, int spp, FloatImage& image,
                  RenderSummary& summary, SampleCounters& counters, FirstHit* hits) {
    ProgressLog progress;
    job.frame.spp = spp;
    for (int y = 0; y < image.height; y += kProgressBandRows) {
        job.y0 = y;
        job.y1 = std::min(image.height, y + kProgressBandRows);
        if (hits) job.first_hits = hits + std::size_t(y) * std::size_t(image.width);
        auto stats = backend.render_rows(job, image.row(y));
        if (!stats) return stats.error();
        counters.add(stats->counters);
        progress(fmt::format("{} of {} rows", job.y1, image.height));
    }
    summary.spp = spp;
    return {};
}

Status compare_with_reference(const std::string& path, const FloatImage& image,
                              RenderSummary& summary) {
    auto ref = read_image(path);
    if (!ref) return ref.error();
    if (ref->width != image.width || ref->height != image.height)
        return make_error(ErrorCode::invalid_argument,
                          "--reference {}: {}x{} image, render is {}x{}", path, ref->width,
                          ref->height, image.width, image.height);
    summary.rmse = rmse(image, *ref);
    summary.relative_mse = relative_mse(image, *ref);
    return {};
}

// The denoiser's spatial filter, its G-buffer made from the render's first hits.
void denoise(FloatImage& image, std::vector<FirstHit> hits, const Camera& camera) {
    coord::denoise_frame(
        image, coord::gbuffer_from_backend_hits(std::move(hits), camera, image.width, image.height),
        camera);
}

}  // namespace

Result<RenderSummary> run_render(const RenderToolOptions& o) {
    if (Status s = check_options(o); !s) return s.error();
    auto kind = tracer::parse_backend_kind(o.backend);
    if (!kind) return kind.error();
    auto scene = load_posed_scene(o);
    if (!scene) return scene.error();
    auto camera = pick_camera(*scene, o, float(o.width) / float(o.height));
    if (!camera) return camera.error();
    *camera = recentre_on_camera(*scene, *camera);  // precision where the pixels are
    auto backend = tracer::create_backend(
        *kind, tracer::BackendOptions{o.threads, o.cl_platform, o.cl_device, o.texture_lod});
    if (!backend) return backend.error();
    if (Status s = (*backend)->set_scene(*scene); !s) return s.error();

    tracer::RenderJob job;
    job.frame = FrameSpec{o.width, o.height, o.frame, o.seed, 0, 0, *camera};
    job.integrator.max_depth = o.max_depth;
    job.integrator.strategy = o.strategy;
    job.integrator.specialise = o.specialise;
    job.integrator.cull_sealed_lights = o.cull_sealed_lights;
    job.integrator.light_selection = o.light_selection;
    job.integrator.light_candidates = o.light_candidates;
    job.y0 = 0;
    job.y1 = o.height;
    FloatImage image(o.width, o.height);
    RenderSummary summary;
    SampleCounters counters;
    const Timer timer;
    std::vector<FirstHit> hits(o.denoise ? std::size_t(o.width) * std::size_t(o.height) : 0);
    FirstHit* hits_out = o.denoise ? hits.data() : nullptr;
    const Status rendered =
        o.seconds
            ? render_for_seconds(**backend, job, *o.seconds, image, summary, counters, hits_out)
            : render_spp(**backend, job, o.spp, image, summary, counters, hits_out);
    if (!rendered) return rendered.error();
    summary.seconds = timer.seconds();
    summary.samples_per_second = double(counters.camera_samples) / summary.seconds;
    summary.rays_per_second = double(counters.rays) / summary.seconds;
    summary.nonfinite_samples = counters.nonfinite_samples;
    if (counters.nonfinite_samples > 0)
        spdlog::warn("{} samples were NaN/Inf and were discarded", counters.nonfinite_samples);
    if (o.denoise) {
        const Timer denoise_timer;
        denoise(image, std::move(hits), *camera);
        summary.denoise_ms = denoise_timer.milliseconds();
        spdlog::info("denoised in {:.1f} ms", summary.denoise_ms);
    }
    if (!o.reference.empty())
        if (Status s = compare_with_reference(o.reference, image, summary); !s) return s.error();
    if (Status s = write_image(o.out, image, o.exposure); !s) return s.error();
    spdlog::info("wrote {} ({}x{}, {} spp)", o.out, o.width, o.height, summary.spp);
    return summary;
}

}  // namespace pathfarm::tools
