// pathfarm-render command line: parses flags into RenderToolOptions and runs the render.
#include <cstdio>
#include <map>

#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include "common/cli/command_line.h"
#include "tools/render/render_tool.h"
#include "tracer-node/backend/backend_cli.h"

namespace {

pathfarm::Vec3 to_vec3(const std::vector<float>& v) { return {v[0], v[1], v[2]}; }

void add_camera_options(CLI::App& app, pathfarm::tools::RenderToolOptions& o,
                        std::vector<float>& look_from, std::vector<float>& look_at,
                        std::vector<float>& up) {
    app.add_option("--camera", o.camera,
                   "Camera index (-1: the scene's first camera or a framing of its bounds)")
        ->capture_default_str();
    app.add_option("--look-from", look_from, "Camera position x y z (overrides scene cameras)")
        ->expected(3);
    app.add_option("--look-at", look_at, "Point the --look-from camera looks at")->expected(3);
    app.add_option("--up", up, "Up vector of the --look-from camera (default 0 1 0)")->expected(3);
    app.add_option("--fov", o.fov_degrees, "Vertical field of view of --look-from, degrees")
        ->capture_default_str();
}

}  // namespace

int main(int argc, char** argv) {
    pathfarm::tools::RenderToolOptions o;
    std::string strategy = "mis";
    std::vector<float> look_from, look_at, up;
    CLI::App app{"pathfarm-render: render a scene in one process (scene, integrator, image)"};
    app.add_option("--scene", o.scene,
                   "Scene file (.gltf .glb .obj[.gz] .ply[.gz]) or builtin:cornell|default")
        ->capture_default_str();
    app.add_option("--out", o.out, "Output: .exr/.pfm (linear float) or .png (tonemapped sRGB)")
        ->capture_default_str();
    app.add_option("--width", o.width, "Image width in pixels")->capture_default_str();
    app.add_option("--height", o.height, "Image height in pixels (aspect = width/height)")
        ->capture_default_str();
    auto* spp = app.add_option("--spp", o.spp, "Samples per pixel")->capture_default_str();
    app.add_option("--seconds", o.seconds, "Render for this many seconds instead of --spp")
        ->excludes(spp);
    app.add_option("--seed", o.seed, "Seed of the per-sample random numbers")
        ->capture_default_str();
    app.add_option("--frame", o.frame, "Frame index (enters the random numbers)")
        ->capture_default_str();
    add_camera_options(app, o, look_from, look_at, up);
    pathfarm::tracer::add_backend_options(app, o.backend, o.threads, o.cl_platform, o.cl_device);
    app.add_option("--max-depth", o.max_depth, "Maximum number of bounces")->capture_default_str();
    app.add_option("--strategy", strategy,
                   "Direct light: mis, light (light sampling only) or bsdf (BSDF sampling only)")
        ->capture_default_str()
        ->check(CLI::IsMember({"mis", "light", "bsdf"}));
    std::string kernel = "specialised";
    app.add_option("--kernel", kernel,
                   "Path-tracing loop: specialised (for the scene's features) or generic")
        ->capture_default_str()
        ->check(CLI::IsMember({"specialised", "generic"}));
    bool no_light_culling = false;
    app.add_flag("--no-light-culling", no_light_culling,
                 "Also sample emitters that a closed surface separates from the camera");
    double time = 0.0;
    auto* time_option =
        app.add_option("--time", time, "Animated scenes: time of the clip's own timeline, seconds");
    app.add_option("--clip", o.clip, "Animation clip by name or index (default: the first)");
    app.add_option("--reference", o.reference,
                   "Reference image of the same size: also print rmse= and rel_mse=");
    app.add_option("--exposure", o.exposure, "Exposure multiplier for PNG output")
        ->capture_default_str();
    if (auto exit_code = pathfarm::parse_command_line(app, argc, argv, "pathfarm-render"))
        return *exit_code;
    const std::map<std::string, pathfarm::LightStrategy> strategies{
        {"mis", pathfarm::LightStrategy::mis},
        {"light", pathfarm::LightStrategy::light_only},
        {"bsdf", pathfarm::LightStrategy::bsdf_only}};
    o.strategy = strategies.at(strategy);
    o.specialise = kernel == "specialised";
    o.cull_sealed_lights = !no_light_culling;
    if (time_option->count() > 0) o.time = time;
    if (!look_from.empty()) o.look_from = to_vec3(look_from);
    if (!look_at.empty()) o.look_at = to_vec3(look_at);
    if (!up.empty()) o.up = to_vec3(up);

    const auto summary = pathfarm::tools::run_render(o);
    if (!summary) {
        std::fprintf(stderr, "pathfarm-render: %s\n", summary.error().message.c_str());
        return summary.error().code == pathfarm::ErrorCode::invalid_argument ? 2 : 1;
    }
    std::string error_figures;
    if (summary->rmse)
        error_figures =
            fmt::format(" rmse={:.6g} rel_mse={:.6g}", *summary->rmse, *summary->relative_mse);
    fmt::print("seconds={:.3f} samples_per_s={:.0f} rays_per_s={:.0f} spp={}{}\n", summary->seconds,
               summary->samples_per_second, summary->rays_per_second, summary->spp, error_figures);
    return 0;
}
