// The coordinator's network mode (DESIGN.md, "The frame"): tracers join at any time (snapshot,
// then commits), each frame's rows are split over them in 4-row units, the next frame's
// commit is prepared while this one renders, rows missing at the deadline (or of a tracer that
// died) are re-issued, and finished frames go to every client in the codec it asked for.
#pragma once

#include <atomic>
#include <optional>
#include <string>

#include "common/base/result.h"
#include "common/scene/scene_model.h"
#include "common/wire/light_sampling.h"

namespace pathfarm::coord {

struct FarmOptions {
    uint16_t tracer_port = 0;  // 0: an ephemeral port, printed at start
    uint16_t client_port = 0;
    std::string bind_address = "0.0.0.0";
    int width = 640, height = 360, spp = 1, max_depth = 8;
    uint32_t seed = 0;
    double fps = 30.0;
    int frames = 0;       // 0: until stopped
    int min_tracers = 1;  // tracers to wait for before frame 0
    int deadline_ms = 10000;
    std::optional<int> clip;
    std::string secret;
    // Tracer and client links in the clear instead of TLS (benchmarks only; both ends must say so).
    bool insecure_plaintext = false;
    // The HTTP port (docs/web.md): browser client, /metrics, /healthz; none: off. Every route
    // but /healthz needs `http_token` (a random one when empty).
    std::optional<uint16_t> http_port;
    std::string http_token;
    std::string https_cert, https_key;  // both: HTTPS and WSS instead of HTTP and WS
    // CSV outputs; their columns are listed in coordinator/frame/farm_stats.h.
    std::string stats_csv;                     // one row per frame
    std::string tracer_stats_csv;              // one row per tracer and frame
    std::string dump_frames;                   // folder for frame_NNNNNN.pfm (linear float)
    std::string balancer = "cost-predictive";  // coordinator/balance/balancer.h
    double speed_smoothing = 0.35;             // kDefaultSpeedSmoothing
    std::string record_costs;  // the time of every work unit (record with one tracer)
    std::string stages_csv;    // the frame loop's stages per frame
    // The real-time loop (docs/realtime.md). fixed_spp: no pacing and no workload scaling, every
    // frame at `spp` and full resolution as fast as the farm goes (the determinism tests).
    bool converge = true;
    // The SVGF-style denoiser (coordinator/converge/denoiser.h): temporal with converging,
    // each frame alone without.
    bool denoise = true;
    // Threads for the display stage's per-pixel work (upscaling, converging, the denoiser);
    // 0: every core. Where the tracers share the coordinator's cores, fewer leave the tracers
    // more time and the denoiser less (docs/denoise.md, "Page faults and threads"). The
    // frames do not depend on it.
    int display_threads = 0;
    // --light-sampler tree|power|auto (IntegratorSettings::light_selection on the tracers)
    wire::LightSampling light_sampling = wire::LightSampling::automatic;
    bool fixed_spp = false;
    // With fixed_spp: samples beyond spp per pixel on average, in [0, 1], placed where history
    // is short (coordinator/pacing/extra_samples.h). Workload scaling chooses its own.
    double extra_samples = 0.0;
    double target_fps = 0.0;                           // frame rate to hold; 0: `fps`
    float min_rr_scale = 0.5f, min_resolution = 0.5f;  // workload scaling's quality floor
    // Share of the frame interval the frames may take (ScalerOptions::headroom): the rest is
    // the loop's own work. Every millisecond of frame is a millisecond of input latency.
    double render_budget = 0.9;
    std::string game = "auto";  // coordinator/game/game.h
    int jpeg_quality = 90;
    // With converging: once every pixel holds this many frames of history and nothing changes,
    // frames render nothing new (the converged image is sent again). 0: always render.
    int converged_frames = 256;
};

Status run_farm(SceneModel scene, const FarmOptions& options, const std::atomic<bool>& stop);

}  // namespace pathfarm::coord
