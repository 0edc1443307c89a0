// pathfarm-coordinator command line: the farm (--tracer-port), the offline frame loop
// (--offline) and pose export (--export-at).
#include <cmath>
#include <csignal>
#include <cstdio>
#include <numeric>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/base/memory.h"
#include "common/cli/command_line.h"
#include "common/net/auth.h"
#include "common/scene/load/scene_loader.h"
#include "coordinator/animation/animator.h"
#include "coordinator/animation/skinning.h"
#include "coordinator/export/obj_export.h"
#include "coordinator/frame/farm_stats.h"
#include "coordinator/http/http_routes.h"
#include "coordinator/offline/offline_driver.h"
#include "coordinator/session/farm_coordinator.h"

namespace {

std::atomic<bool> g_stop{false};
void request_stop(int) { g_stop = true; }

int fail(const pathfarm::Error& e) {
    std::fprintf(stderr, "pathfarm-coordinator: %s\n", e.message.c_str());
    return e.code == pathfarm::ErrorCode::invalid_argument ? 2 : 1;
}

pathfarm::Result<std::optional<int>> clip_index(const pathfarm::SceneModel& scene,
                                                const std::string& name) {
    if (name.empty()) return std::optional<int>();
    auto clip = pathfarm::coord::find_clip(scene, name);
    if (!clip) return clip.error();
    return std::optional<int>(*clip);
}

int export_pose(pathfarm::SceneModel scene, const std::string& clip_name, double at,
                const std::string& path) {
    if (!std::isfinite(at))  // a NaN time posed the clip somewhere, silently
        return fail({pathfarm::ErrorCode::invalid_argument,
                     fmt::format("--export-at {}: must be finite", at)});
    if (!scene.animations.empty()) {
        auto clip = pathfarm::coord::find_clip(scene, clip_name.empty() ? "0" : clip_name);
        if (!clip) return fail(clip.error());
        pathfarm::coord::apply_clip(scene, *clip, float(at));
    } else if (!clip_name.empty()) {
        return fail({pathfarm::ErrorCode::invalid_argument,
                     "--clip " + clip_name + ": scene has no animations"});
    }
    if (auto s = pathfarm::coord::export_posed_obj(pathfarm::coord::pose_scene(scene), path); !s)
        return fail(s.error());
    spdlog::info("wrote {} (time {} s)", path, at);
    return 0;
}

int offline(pathfarm::SceneModel scene, const std::string& clip_name,
            pathfarm::coord::OfflineOptions o) {
    auto clip = clip_index(scene, clip_name);
    if (!clip) return fail(clip.error());
    o.clip = *clip;
    auto stats = pathfarm::coord::run_offline(std::move(scene), o);
    if (!stats) return fail(stats.error());
    using Stats = pathfarm::coord::OfflineFrameStats;
    const auto mean = [&](auto field) {
        const double n = double(std::max<std::size_t>(stats->size() - 1, 1));
        return std::accumulate(stats->begin() + 1, stats->end(), 0.0,
                               [&](double a, const Stats& s) { return a + double(s.*field); }) /
               n;
    };
    std::printf(
        "frames=%zu snapshot_bytes=%zu commit_bytes_per_frame=%.0f animate_ms=%.3f accel_ms=%.3f "
        "commit_ms=%.3f replica_ok=1\n",
        stats->size(), stats->front().commit_bytes, mean(&Stats::commit_bytes),
        mean(&Stats::animate_ms), mean(&Stats::accel_ms), mean(&Stats::commit_ms));
    return 0;
}

// Everything the command line asks for.
struct Command {
    std::string scene_spec, export_path, clip_name, secret_file, stats_csv, http_token_file;
    double export_at = 0.0, fps = 30.0;
    int frames = -1;  // unset: the mode's default
    CLI::Option* frames_option = nullptr;
    bool offline_mode = false, no_converge = false;
    std::string denoise = "on", light_sampler = "auto";
    pathfarm::coord::OfflineOptions o;
    pathfarm::coord::FarmOptions f;
    CLI::Option* tracer_port = nullptr;
    CLI::Option* http_port = nullptr;
    uint16_t http_port_value = 0;
};

int farm(pathfarm::SceneModel scene, const Command& c, pathfarm::coord::FarmOptions f) {
    auto secret = pathfarm::net::load_secret(c.secret_file);
    if (!secret) return fail(secret.error());
    f.secret = *secret;
    if (c.http_port->count() > 0) {  // the browser's token: a fixed one, or a new one each run
        f.http_port = c.http_port_value;
        auto token = c.http_token_file.empty()
                         ? pathfarm::Result<std::string>(pathfarm::coord::random_token())
                         : pathfarm::coord::read_token_file(c.http_token_file);
        if (!token) return fail(token.error());
        f.http_token = *token;
    } else if (!c.http_token_file.empty() || !f.https_cert.empty() || !f.https_key.empty()) {
        return fail({pathfarm::ErrorCode::invalid_argument,
                     "--http-token-file, --https-cert and --https-key need --http-port"});
    }
    if (f.https_cert.empty() != f.https_key.empty())
        return fail(
            {pathfarm::ErrorCode::invalid_argument, "--https-cert and --https-key go together"});
    const std::string& clip_name = c.clip_name;
    auto clip = clip_index(scene, clip_name);
    if (!clip) return fail(clip.error());
    f.clip = *clip;
    std::signal(SIGINT, request_stop);
    std::signal(SIGTERM, request_stop);
    if (auto s = pathfarm::coord::run_farm(std::move(scene), f, g_stop); !s) return fail(s.error());
    return 0;
}

std::string columns(std::string_view list) { return " (columns: " + std::string(list) + ")"; }

void add_scene_options(CLI::App& app, Command& c) {
    app.add_option("--scene", c.scene_spec, "Scene file (.gltf .glb .obj .ply) or builtin:NAME")
        ->required();
    c.frames_option = app.add_option(
        "--frames", c.frames, "Frames to run (offline default 60; farm default: until stopped)");
    app.add_option("--fps", c.fps, "Game clock: frame f shows time f / fps")->capture_default_str();
    app.add_option("--clip", c.clip_name, "Animation clip by name or index (default: the first)");
    app.add_option("--stats-csv", c.stats_csv,
                   "One row per frame" + columns(pathfarm::coord::kFrameStatsColumns) +
                       "; with --offline" + columns(pathfarm::coord::kOfflineStatsColumns));
}

void add_farm_options(CLI::App& app, Command& c) {
    pathfarm::coord::FarmOptions& f = c.f;
    c.tracer_port =
        app.add_option("--tracer-port", f.tracer_port, "Run the farm: port for tracers (0: any)");
    app.add_option("--client-port", f.client_port, "Port for clients (0: any)")
        ->capture_default_str();
    app.add_option("--bind", f.bind_address, "Address to listen on")->capture_default_str();
    app.add_option("--width", f.width, "Frame width")->capture_default_str();
    app.add_option("--height", f.height, "Frame height")->capture_default_str();
    app.add_option("--spp", f.spp, "Samples per pixel per frame")->capture_default_str();
    app.add_option("--seed", f.seed, "Seed of the per-sample random numbers")
        ->capture_default_str();
    app.add_option("--max-depth", f.max_depth, "Maximum number of bounces")->capture_default_str();
    app.add_option("--balancer", f.balancer,
                   "Row balancing: none, robin-hood, perfect, perfect-smooth, cost-predictive")
        ->capture_default_str()
        ->check(CLI::IsMember(
            {"none", "robin-hood", "perfect", "perfect-smooth", "cost-predictive", "ours"}));
    app.add_option("--speed-smoothing", f.speed_smoothing,
                   "cost-predictive: weight of the last frame in each tracer's smoothed speed "
                   "(1: no smoothing)")
        ->capture_default_str()
        ->check(CLI::Range(0.01, 1.0));
    app.add_option("--record-costs", f.record_costs,
                   "Per frame and work unit, for the simulator (record with one tracer)" +
                       columns(pathfarm::coord::kUnitCostColumns));
    app.add_option("--secret-file", c.secret_file,
                   "File holding the shared secret (else $PATHFARM_SECRET)");
    app.add_flag("--insecure-plaintext", f.insecure_plaintext,
                 "Benchmarks only: no TLS on tracer and client links (commits, tiles and frames "
                 "in the clear); tracers and clients must say so too");
    app.add_option("--tracer-stats-csv", f.tracer_stats_csv,
                   "Per tracer and frame" + columns(pathfarm::coord::kTracerStatsColumns));
    app.add_option("--stages-csv", f.stages_csv,
                   "Per frame: the frame loop's stages" + columns(pathfarm::coord::kStageColumns));
    app.add_option("--dump-frames", f.dump_frames,
                   "Folder for every assembled frame as linear float PFM");
    app.add_option("--deadline-ms", f.deadline_ms, "Re-issue rows still missing after this long")
        ->capture_default_str();
    app.add_option("--min-tracers", f.min_tracers, "Tracers to wait for before the first frame")
        ->capture_default_str();
    c.http_port =
        app.add_option("--http-port", c.http_port_value,
                       "HTTP port (0: any): the browser client, /metrics, /healthz; "
                       "its URL with the access token is printed at start (default: off)");
    app.add_option("--http-token-file", c.http_token_file,
                   "File holding the HTTP port's access token (default: a random one per run)");
    app.add_option("--https-cert", c.f.https_cert,
                   "PEM certificate chain: the HTTP port serves HTTPS and WSS (with --https-key)");
    app.add_option("--https-key", c.f.https_key, "PEM private key of --https-cert");
}

void add_realtime_options(CLI::App& app, Command& c) {  // docs/realtime.md
    pathfarm::coord::FarmOptions& f = c.f;
    app.add_option("--target-fps", f.target_fps,
                   "Frame rate to hold by pacing and workload scaling (0: --fps)")
        ->capture_default_str();
    app.add_flag("--fixed-spp", f.fixed_spp,
                 "No pacing and no workload scaling: every frame at --spp and full size, as fast "
                 "as the farm goes");
    app.add_option("--extra-samples", f.extra_samples,
                   "With --fixed-spp: samples beyond --spp per pixel on average, in [0, 1], "
                   "where history is short (workload scaling chooses its own)")
        ->capture_default_str();
    app.add_flag("--no-converge", c.no_converge,
                 "Send each frame's own samples (no blending with reprojected history)");
    app.add_option("--denoise", c.denoise,
                   "Spatio-temporal denoiser on every frame (temporal with converging, each "
                   "frame alone with --no-converge): on or off")
        ->capture_default_str()
        ->check(CLI::IsMember({"on", "off"}));
    app.add_option("--display-threads", f.display_threads,
                   "Threads for the display stage's upscaling, converging and denoising; 0: "
                   "every core (fewer where tracers share this machine's cores)")
        ->capture_default_str()
        ->check(CLI::Range(0, 1024));
    app.add_option("--light-sampler", c.light_sampler,
                   "Emitter choice for next-event estimation on the tracers: tree (by importance "
                   "to the shading point), power, or auto (the tree where the scene's emitters "
                   "differ in what they give its surfaces, else power)")
        ->capture_default_str()
        ->check(CLI::IsMember({"tree", "power", "auto"}));
    app.add_option("--min-rr-scale", f.min_rr_scale,
                   "Workload scaling's floor on the Russian-roulette survival scale")
        ->capture_default_str();
    app.add_option("--min-resolution", f.min_resolution,
                   "Workload scaling's floor on the render size over --width/--height")
        ->capture_default_str();
    app.add_option("--render-budget", f.render_budget,
                   "Share of the frame interval workload scaling fills with rendering: higher "
                   "uses more of the tracers for quality, lower answers input sooner")
        ->capture_default_str();
    app.add_option("--game", f.game,
                   "Game logic: auto (builtin:default's game there, else free-camera), "
                   "free-camera, default")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "free-camera", "default"}));
    app.add_option("--converged-frames", f.converged_frames,
                   "Converging: once every pixel has this many frames and nothing changes, render "
                   "nothing new (0: always render)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    app.add_option("--jpeg-quality", f.jpeg_quality, "Quality of JPEG frames to clients")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
}

void add_offline_options(CLI::App& app, Command& c) {  // offline loop and pose export
    app.add_flag("--offline", c.offline_mode,
                 "Run the frame loop without a network, with an in-process replica");
    app.add_option("--rebuild-factor", c.o.rebuild_factor,
                   "Rebuild a refitted BVH past this SAH ratio")
        ->capture_default_str();
    app.add_flag("--bvh-nodes", c.o.bvh_nodes,
                 "Offline: the replica asks for BVH nodes, as OpenCL tracers do");
    auto* at = app.add_option("--export-at", c.export_at,
                              "Export the pose at this time of the clip's own timeline");
    app.add_option("--export", c.export_path,
                   "OBJ file for --export-at (world-space posed triangles)")
        ->needs(at);
    at->needs("--export");
}

int run(Command& c) {
    const bool farm_mode = c.tracer_port->count() > 0;
    if (c.export_path.empty() && !c.offline_mode && !farm_mode) {
        std::fprintf(
            stderr,
            "pathfarm-coordinator: nothing to do (use --tracer-port, --offline or --export-at)\n");
        return 2;
    }
    if (c.frames_option->count() > 0 && c.frames < 0)  // was taken as unset, silently
        return fail({pathfarm::ErrorCode::invalid_argument,
                     fmt::format("--frames {}: must be >= 0", c.frames)});
    auto scene = pathfarm::load_scene(c.scene_spec);
    if (!scene) return fail(scene.error());
    if (!c.export_path.empty()) {
        if (const int rc = export_pose(*scene, c.clip_name, c.export_at, c.export_path);
            rc != 0 || (!c.offline_mode && !farm_mode))
            return rc;
    }
    if (farm_mode) {
        c.f.frames = std::max(c.frames, 0);
        c.f.fps = c.fps;
        c.f.stats_csv = c.stats_csv;
        c.f.converge = !c.no_converge;
        c.f.denoise = c.denoise == "on";
        c.f.light_sampling = c.light_sampler == "tree" ? pathfarm::wire::LightSampling::tree
                             : c.light_sampler == "power"
                                 ? pathfarm::wire::LightSampling::power
                                 : pathfarm::wire::LightSampling::automatic;
        return farm(std::move(*scene), c, c.f);
    }
    c.o.frames = c.frames < 0 ? 60 : c.frames;
    c.o.fps = c.fps;
    c.o.stats_csv = c.stats_csv;
    return offline(std::move(*scene), c.clip_name, c.o);
}

}  // namespace

int main(int argc, char** argv) {
    Command c;
    CLI::App app{
        "pathfarm-coordinator: scene graph, animation, BVH maintenance, commits and the farm"};
    add_scene_options(app, c);
    add_farm_options(app, c);
    add_realtime_options(app, c);
    add_offline_options(app, c);
    if (auto exit_code = pathfarm::parse_command_line(app, argc, argv, "pathfarm-coordinator"))
        return *exit_code;
    // Each frame allocates the buffers the last one freed: keep them mapped (memory.h).
    if (!pathfarm::keep_freed_memory()) spdlog::debug("the C library keeps its own malloc tuning");
    return run(c);
}
