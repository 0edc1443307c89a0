// pathfarm-render: the whole pipeline in one process (scene -> backend -> image file).
#pragma once

#include <optional>
#include <string>

#include "common/base/result.h"
#include "common/render/path_tracer.h"

namespace pathfarm::tools {

struct RenderToolOptions {
    std::string scene = "builtin:default";
    std::string out = "render.exr";
    std::string backend = "embree";
    int width = 640;
    int height = 360;
    int spp = 16;
    // Set: render passes until this much time has passed (spp ignored); must be positive.
    std::optional<double> seconds;
    uint32_t seed = 0;
    uint32_t frame = 0;
    int camera = -1;  // -1: the scene's first camera, or a framing of its bounds
    // An explicit view overrides the scene's cameras (for benchmarks against other renderers).
    std::optional<Vec3> look_from, look_at;
    Vec3 up{0.0f, 1.0f, 0.0f};
    float fov_degrees = 45.0f;   // vertical, with look_from
    std::string reference;       // if set: report RMSE and relative MSE against this image
    std::optional<double> time;  // animated scenes: pose at this time of the clip's timeline
    std::string clip;            // clip name or index; default the first
    int threads = 0;
    int cl_platform = 0;  // OpenCL backend: platform and device index
    int cl_device = 0;
    bool texture_lod = true;  // BackendOptions::texture_lod
    int max_depth = 8;
    LightStrategy strategy = LightStrategy::mis;
    bool specialise = true;          // the path-tracing loop specialised for the scene's features
    bool cull_sealed_lights = true;  // IntegratorSettings::cull_sealed_lights
    LightSelection light_selection = IntegratorSettings{}.light_selection;
    int light_candidates = IntegratorSettings{}.light_candidates;
    float exposure = 1.0f;
    // The denoiser's spatial filter on the finished image (coordinator/converge/denoiser.h),
    // guided by the first hits of the pixel centres.
    bool denoise = false;
};

struct RenderSummary {
    double seconds = 0.0;
    int spp = 0;
    double samples_per_second = 0.0;
    double rays_per_second = 0.0;
    uint64_t nonfinite_samples = 0;
    std::optional<double> rmse, relative_mse;  // against RenderToolOptions::reference
    double denoise_ms = 0.0;
};

Result<RenderSummary> run_render(const RenderToolOptions& options);

}  // namespace pathfarm::tools
