// pathfarm-render: the whole pipeline in one process (scene -> backend -> image file).
#pragma once

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
    double seconds = 0.0;  // > 0: render passes until this much time has passed (spp ignored)
    uint32_t seed = 0;
    uint32_t frame = 0;
    int camera = -1;  // -1: the scene's first camera, or a framing of its bounds
    int threads = 0;
    int max_depth = 8;
    LightStrategy strategy = LightStrategy::mis;
    float exposure = 1.0f;
};

struct RenderSummary {
    double seconds = 0.0;
    int spp = 0;
    double samples_per_second = 0.0;
    double rays_per_second = 0.0;
    uint64_t nonfinite_samples = 0;
};

Result<RenderSummary> run_render(const RenderToolOptions& options);

}  // namespace pathfarm::tools
