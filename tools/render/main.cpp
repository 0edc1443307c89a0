// pathfarm-render command line: parses flags into RenderToolOptions and runs the render.
#include <cstdio>
#include <map>

#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include "common/base/log.h"
#include "tools/render/render_tool.h"

int main(int argc, char** argv) {
    pathfarm::tools::RenderToolOptions o;
    std::string log_level = "info";
    CLI::App app{"pathfarm-render: render a scene in one process (scene, integrator, image file)"};
    app.add_option("--scene", o.scene,
                   "Scene file (.gltf .glb .obj[.gz] .ply[.gz]) or builtin:cornell|default")
        ->capture_default_str();
    app.add_option("--out", o.out,
                   "Output image: .exr/.pfm (linear float) or .png (tonemapped sRGB)")
        ->capture_default_str();
    app.add_option("--width", o.width, "Image width in pixels")->capture_default_str();
    app.add_option("--height", o.height, "Image height in pixels (aspect = width/height)")
        ->capture_default_str();
    auto* spp = app.add_option("--spp", o.spp, "Samples per pixel")->capture_default_str();
    app.add_option("--seconds", o.seconds, "Render for this many seconds instead of a fixed spp")
        ->excludes(spp);
    app.add_option("--seed", o.seed, "Seed of the per-sample random numbers")
        ->capture_default_str();
    app.add_option("--frame", o.frame, "Frame index (enters the random numbers)")
        ->capture_default_str();
    app.add_option("--camera", o.camera,
                   "Camera index (-1: the scene's first camera or a framing of its bounds)")
        ->capture_default_str();
    app.add_option("--threads", o.threads, "Render threads (0: all)")->capture_default_str();
    app.add_option("--max-depth", o.max_depth, "Maximum number of bounces")->capture_default_str();
    app.add_option("--backend", o.backend, "Render backend")
        ->capture_default_str()
        ->check(CLI::IsMember({"embree", "opencl"}));
    const std::map<std::string, pathfarm::LightStrategy> strategies{
        {"mis", pathfarm::LightStrategy::mis},
        {"light", pathfarm::LightStrategy::light_only},
        {"bsdf", pathfarm::LightStrategy::bsdf_only}};
    app.add_option("--strategy", o.strategy,
                   "Direct-light estimator: mis, light (NEE only) or bsdf")
        ->transform(CLI::CheckedTransformer(strategies))
        ->default_str("mis");
    app.add_option("--exposure", o.exposure, "Exposure multiplier for PNG output")
        ->capture_default_str();
    app.add_option("--log-level", log_level, "trace, debug, info, warn, error")
        ->capture_default_str();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    pathfarm::init_logging("pathfarm-render", log_level);
    const auto summary = pathfarm::tools::run_render(o);
    if (!summary) {
        std::fprintf(stderr, "pathfarm-render: %s\n", summary.error().message.c_str());
        return summary.error().code == pathfarm::ErrorCode::invalid_argument ? 2 : 1;
    }
    fmt::print("seconds={:.3f} spp={} samples_per_s={:.0f} rays_per_s={:.0f}\n", summary->seconds,
               summary->spp, summary->samples_per_second, summary->rays_per_second);
    return 0;
}
