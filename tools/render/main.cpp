// pathfarm-render command line: parses flags into RenderToolOptions and runs the render.
#include <algorithm>
#include <cstdio>
#include <map>

#include <fmt/core.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/base/memory.h"
#include "common/cli/command_line.h"
#include "tools/render/render_tool.h"
#include "tracer-node/backend/backend_cli.h"

namespace {

pathfarm::Vec3 to_vec3(const std::vector<float>& v) { return {v[0], v[1], v[2]}; }

// Flags parsed into strings and vectors first, converted by finish_options.
struct CommandLine {
    pathfarm::tools::RenderToolOptions o;
    std::string strategy = "mis", kernel = "specialised", light_sampler;
    std::vector<float> look_from, look_at, up;
    bool no_light_culling = false;
    double time = 0.0, seconds = 0.0;
    CLI::Option *time_option = nullptr, *seconds_option = nullptr;
};

void add_image_options(CLI::App& app, CommandLine& c) {
    pathfarm::tools::RenderToolOptions& o = c.o;
    app.add_option("--scene", o.scene,
                   "Scene file (.gltf .glb .obj[.gz] .ply[.gz]) or builtin:cornell|default")
        ->capture_default_str();
    app.add_option("--out", o.out, "Output: .exr/.pfm (linear float) or .png (tonemapped sRGB)")
        ->capture_default_str();
    app.add_option("--width", o.width, "Image width in pixels")->capture_default_str();
    app.add_option("--height", o.height, "Image height in pixels (aspect = width/height)")
        ->capture_default_str();
    auto* spp = app.add_option("--spp", o.spp, "Samples per pixel")->capture_default_str();
    c.seconds_option =
        app.add_option("--seconds", c.seconds, "Render for this many seconds instead of --spp")
            ->excludes(spp);
    app.add_option("--seed", o.seed, "Seed of the per-sample random numbers")
        ->capture_default_str();
    app.add_option("--frame", o.frame, "Frame index (enters the random numbers)")
        ->capture_default_str();
    app.add_option("--reference", o.reference,
                   "Reference image of the same size: also print rmse= and rel_mse=");
    app.add_option("--exposure", o.exposure, "Exposure multiplier for PNG output")
        ->capture_default_str();
}

void add_camera_options(CLI::App& app, CommandLine& c) {
    app.add_option("--camera", c.o.camera,
                   "Camera index (-1: the scene's first camera or a framing of its bounds)")
        ->capture_default_str();
    CLI::Option* look_from = app.add_option("--look-from", c.look_from,
                                            "Camera position x y z (overrides scene cameras)")
                                 ->expected(3);
    // Without --look-from these were ignored, even a NaN: the scene's camera rendered silently.
    app.add_option("--look-at", c.look_at, "Point the --look-from camera looks at")
        ->expected(3)
        ->needs(look_from);
    app.add_option("--up", c.up, "Up vector of the --look-from camera (default 0 1 0)")
        ->expected(3)
        ->needs(look_from);
    app.add_option("--fov", c.o.fov_degrees, "Vertical field of view of --look-from, degrees")
        ->capture_default_str()
        ->needs(look_from);
    c.time_option = app.add_option("--time", c.time,
                                   "Animated scenes: time of the clip's own timeline, seconds");
    app.add_option("--clip", c.o.clip, "Animation clip by name or index (default: the first)");
}

void add_integrator_options(CLI::App& app, CommandLine& c) {
    app.add_option("--max-depth", c.o.max_depth, "Maximum number of bounces")
        ->capture_default_str();
    app.add_option("--strategy", c.strategy,
                   "Direct light: mis, light (light sampling only) or bsdf (BSDF sampling only)")
        ->capture_default_str()
        ->check(CLI::IsMember({"mis", "light", "bsdf"}));
    app.add_option("--kernel", c.kernel,
                   "Path-tracing loop: specialised (for the scene's features) or generic")
        ->capture_default_str()
        ->check(CLI::IsMember({"specialised", "generic"}));
    c.light_sampler = pathfarm::light_selection_name(c.o.light_selection);
    app.add_option("--light-sampler", c.light_sampler,
                   "Emitter choice for next-event estimation: tree (by importance to the shading "
                   "point), power, or auto (the tree where the scene's emitters differ in what "
                   "they give its surfaces, else power)")
        ->capture_default_str()
        ->check(CLI::IsMember({"tree", "power", "auto"}));
    app.add_option("--light-candidates", c.o.light_candidates,
                   "Resampled light selection: candidates drawn per light sample, one traced "
                   "(chosen by its unshadowed contribution); 1: off")
        ->capture_default_str()
        ->check(CLI::Range(1, pathfarm::kMaxLightCandidates));
    app.add_flag("--no-light-culling", c.no_light_culling,
                 "Also sample emitters that a closed surface separates from the camera");
    app.add_flag("--denoise", c.o.denoise,
                 "Denoise the finished image (the farm denoiser's spatial filter, guided by the "
                 "pixel centres' first hits); the output is still linear");
}

pathfarm::tools::RenderToolOptions finish_options(CommandLine& c) {
    pathfarm::tools::RenderToolOptions o = c.o;
    const std::map<std::string, pathfarm::LightStrategy> strategies{
        {"mis", pathfarm::LightStrategy::mis},
        {"light", pathfarm::LightStrategy::light_only},
        {"bsdf", pathfarm::LightStrategy::bsdf_only}};
    o.strategy = strategies.at(c.strategy);
    o.specialise = c.kernel == "specialised";
    o.cull_sealed_lights = !c.no_light_culling;
    o.light_selection = *pathfarm::parse_light_selection(c.light_sampler);  // CLI checked it
    if (c.time_option->count() > 0) o.time = c.time;
    if (c.seconds_option->count() > 0) o.seconds = c.seconds;
    if (!c.look_from.empty()) o.look_from = to_vec3(c.look_from);
    if (!c.look_at.empty()) o.look_at = to_vec3(c.look_at);
    if (!c.up.empty()) o.up = to_vec3(c.up);
    return o;
}

}  // namespace

int main(int argc, char** argv) {
    CommandLine c;
    CLI::App app{"pathfarm-render: render a scene in one process (scene, integrator, image)"};
    add_image_options(app, c);
    add_camera_options(app, c);
    pathfarm::tracer::add_backend_options(app, c.o.backend, c.o.threads, c.o.cl_platform,
                                          c.o.cl_device, c.o.texture_lod);
    add_integrator_options(app, c);
    if (auto exit_code = pathfarm::parse_command_line(app, argc, argv, "pathfarm-render"))
        return *exit_code;
    // One frame, each buffer allocated once and touched once: on huge pages, a fault per 2 MiB
    // instead of per 4 KiB (about 500 bytes a pixel: image, first hits, G-buffer, denoiser).
    const std::size_t pixels = std::size_t(c.o.width) * std::size_t(std::max(c.o.height, 0));
    if (!pathfarm::back_main_heap_with_huge_pages(
            std::min(pixels * 512 + (std::size_t(64) << 20), std::size_t(1) << 30)))
        spdlog::debug("the main heap is not on huge pages");
    const auto summary = pathfarm::tools::run_render(finish_options(c));
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
