// The farm frame loop: the frame pipeline prepares frame N (and N+1 while N renders), the
// tracer pool renders it, converging and the client hub show it. docs/architecture.md walks
// one frame through these files.
#include "coordinator/session/farm_coordinator.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include <spdlog/spdlog.h>

#include "common/base/folder.h"
#include "common/base/timer.h"
#include "common/commit/commit_codec.h"
#include "common/film/extra_samples_codec.h"
#include "common/film/image_io.h"
#include "common/film/resample.h"
#include "common/net/framing.h"
#include "common/wire/messages.h"
#include "coordinator/converge/gbuffer.h"
#include "coordinator/frame/farm_stats.h"
#include "coordinator/frame/frame_pipeline.h"
#include "coordinator/http/web_port.h"
#include "coordinator/pacing/extra_samples.h"
#include "coordinator/pacing/workload_scaler.h"
#include "coordinator/session/client_hub.h"
#include "coordinator/session/farm_options_check.h"
#include "coordinator/session/frame_display.h"
#include "coordinator/session/tracer_pool.h"

namespace pathfarm::coord {
namespace {

using Clock = std::chrono::steady_clock;

// Frame N's commit as envelopes (with BVH ops for tracers that asked) and its view.
struct PreparedFrame {
    FrameUpdate update;
    std::vector<std::string> plain, with_bvh;
    std::size_t plain_bytes = 0;
    FrameView view;  // camera, instances, deformed, cut; the G-buffer comes with the tiles
};

// Starts frame f no earlier than one interval after frame f - 1 (a held frame rate).
class Pacer {
public:
    explicit Pacer(double fps)
        : interval_(std::chrono::duration_cast<Clock::duration>(
              std::chrono::duration<double>(1.0 / fps))) {}
    void wait() {
        std::this_thread::sleep_until(next_);
        next_ = std::max(Clock::now(), next_ + interval_);
    }

private:
    Clock::duration interval_;
    Clock::time_point next_ = Clock::now();
};

class Farm {
public:
    // `framing`: the camera of a scene that has none (framed from its bounds).
    Farm(SceneModel scene, const FarmOptions& o, std::unique_ptr<Balancer> balancer,
         const Camera& framing);
    Status start_game() { return pipeline_.start_game(o_.game, scene_name_); }
    Status run(const std::atomic<bool>& stop);

private:
    double target_fps() const { return o_.target_fps > 0.0 ? o_.target_fps : o_.fps; }
    Status listen(net::NetService& net);
    Result<uint16_t> open_http_port();
    PreparedFrame prepare(uint64_t frame);
    bool converged_and_unchanged(const PreparedFrame& p);
    void begin_frame(FrameWork work, const PreparedFrame& p, bool render);
    FrameWork next_work(uint64_t frame);
    void plan_extra_samples(FrameWork& w, double budget);
    void observe_frame_time(double frame_ms, const FrameOutcome& outcome);
    void display(PreparedFrame& p, FrameOutcome outcome, double frame_ms, bool rendered);
    void log_rate(uint64_t frame, int completed);
    void shut_down();

    FarmOptions o_;
    std::string scene_name_;
    FramePipeline pipeline_;
    TracerPool tracers_;
    FarmMetrics metrics_;
    ClientHub clients_;
    std::unique_ptr<WebPort> web_;          // --http-port
    std::optional<WorkloadScaler> scaler_;  // none with --fixed-spp
    FrameWork work_;                        // of the frame being rendered
    Timer run_clock_;                       // since the farm started: stats' wall_ms
    CsvWriter stages_;
    FrameDisplay display_;  // after what it uses: clients_, run_clock_
    double last_line_s_ = 0.0;
    int completed_at_last_line_ = 0;
};

Farm::Farm(SceneModel scene, const FarmOptions& o, std::unique_ptr<Balancer> balancer,
           const Camera& framing)
    : o_(o),
      scene_name_(scene.name),
      pipeline_(std::move(scene), PipelineOptions{o.clip, 1.5}),
      tracers_(std::move(balancer), std::chrono::milliseconds(o.deadline_ms)),
      clients_(o.jpeg_quality, metrics_),
      stages_(o.stages_csv, kStageColumns),
      display_(o_, clients_, metrics_, run_clock_) {
    SceneGraph& graph = pipeline_.graph();
    // A scene without a camera is framed from its bounds (DESIGN.md), as pathfarm-render
    // frames it, and the replicas get that camera like any other.
    if (graph.state().cameras.empty()) graph.set_camera(std::nullopt, framing, true);
    RenderSettings s = graph.state().settings;
    s.width = o.width;
    s.height = o.height;
    s.spp = o.spp;
    s.max_depth = o.max_depth;
    s.seed = o.seed;
    graph.set_settings(s);
}

Status Farm::listen(net::NetService& net) {
    const auto config = [&](uint16_t port, net::PeerRole role, uint32_t max_bytes) {
        return net::ServerConfig{port,
                                 o_.bind_address,
                                 {role},
                                 o_.secret,
                                 max_bytes,
                                 std::chrono::milliseconds(5000),
                                 !o_.insecure_plaintext};
    };
    auto tracer_port =
        net.listen(config(o_.tracer_port, net::PeerRole::tracer, net::kMaxFromTracerBytes),
                   [this](auto s) { tracers_.add(std::move(s)); });
    if (!tracer_port) return tracer_port.error();
    auto client_port =
        net.listen(config(o_.client_port, net::PeerRole::client, net::kMaxFromClientBytes),
                   [this](auto s) { clients_.add(std::move(s)); });
    if (!client_port) return client_port.error();
    auto http_port = open_http_port();
    if (!http_port) return http_port.error();
    std::printf("listening tracer_port=%u client_port=%u http_port=%u\n", unsigned(*tracer_port),
                unsigned(*client_port), unsigned(*http_port));
    if (web_) {
        const bool any = o_.bind_address == "0.0.0.0" || o_.bind_address == "::";
        std::printf("browser client: %s\n", web_->url(any ? "127.0.0.1" : o_.bind_address).c_str());
    }
    std::fflush(stdout);
    return {};
}

// The browsers join the client hub; 0 when the port is off.
Result<uint16_t> Farm::open_http_port() {
    if (!o_.http_port) return uint16_t(0);
    BrowserEvents events;
    events.joined = [this](uint64_t id, bool h264) { clients_.browser_joined(id, h264); };
    events.left = [this](uint64_t id) { clients_.browser_left(id); };
    events.needs_key = [this](uint64_t id) { clients_.browser_needs_key(id); };
    events.input = [this](uint64_t id, const PlayerInput& in) { clients_.browser_input(id, in); };
    std::optional<TlsFiles> tls;
    if (!o_.https_cert.empty()) tls = TlsFiles{o_.https_cert, o_.https_key};
    web_ = std::make_unique<WebPort>(o_.http_token, metrics_, std::move(events), std::move(tls));
    clients_.attach(web_.get());
    return web_->start(o_.bind_address, *o_.http_port);
}

PreparedFrame Farm::prepare(uint64_t frame) {
    PreparedFrame p;
    // The fixed game clock (DESIGN.md, "Time"); input takes effect at frame boundaries.
    p.update = pipeline_.advance(frame, double(frame) / o_.fps, clients_.take_inputs(frame));
    const EncodedCommit plain = encode_commit(pipeline_.commit(p.update, false));
    p.plain_bytes = plain.total_bytes();
    p.plain = wire::encode_commit_envelopes(plain);
    p.with_bvh = wire::encode_commit_envelopes(encode_commit(pipeline_.commit(p.update, true)));
    p.view = pipeline_.view(p.update);
    return p;
}

// A still, unchanged view whose every pixel has converged renders nothing new.
bool Farm::converged_and_unchanged(const PreparedFrame& p) {
    return o_.converge && o_.converged_frames > 0 && p.update.unchanged &&
           display_.min_history_frames() >= float(o_.converged_frames);
}

FrameWork Farm::next_work(uint64_t frame) {
    // Converging reprojects with the tracers' first hits.
    FrameWork w;
    w.frame = frame;
    w.width = o_.width;
    w.height = o_.height;
    w.spp = o_.spp;
    w.seed = o_.seed;
    w.max_depth = o_.max_depth;
    w.first_hits = o_.converge || o_.denoise;
    w.light_sampling = o_.light_sampling;
    double extra = o_.extra_samples;
    if (scaler_) {
        const QualityLevel& l = scaler_->level();
        w.width = std::max(8, int(std::lround(o_.width * l.resolution)));
        w.height = std::max(8, int(std::lround(o_.height * l.resolution)));
        w.spp = l.spp;
        w.rr_scale = l.rr_scale;
        extra = l.extra;
    }
    plan_extra_samples(w, extra);
    return w;
}

// Extra samples go where the history is short as frame N - 2 left it: N - 1 may still be
// showing, and waiting for a fixed frame keeps the plan independent of the display's timing.
void Farm::plan_extra_samples(FrameWork& w, double budget) {
    if (!(budget > 0.0)) return;
    std::vector<float> history;
    if (w.frame >= 2) history = display_.history_after(w.frame - 2);
    if (w.width != o_.width || w.height != o_.height) history.clear();
    std::vector<uint8_t> map =
        coord::plan_extra_samples(history, w.width, w.height, budget, w.frame);
    std::size_t total = 0;
    for (const uint8_t e : map)
        total += e;
    w.extra = double(total) / double(map.size());
    if (total == 0) return;
    w.extra_samples_zstd = encode_extra_samples(map);
    w.extra_map = std::make_shared<const std::vector<uint8_t>>(std::move(map));
}

void Farm::begin_frame(FrameWork work, const PreparedFrame& p, bool render) {
    work_ = std::move(work);
    const uint64_t frame = work_.frame;
    // Real time prepares frame N+1 only after N: the snapshot describes N while it renders.
    const FrameCommit commit{&p.plain, &p.with_bvh,
                             [this, frame](bool with_bvh) {
                                 return wire::encode_commit_envelopes(
                                     encode_commit(pipeline_.snapshot(frame, with_bvh)));
                             },
                             scaler_.has_value()};
    tracers_.begin(work_, commit, render);
}

// The slowest tracer's render time is the part of the frame that scales with the quality.
void Farm::observe_frame_time(double frame_ms, const FrameOutcome& outcome) {
    if (!scaler_) return;
    const bool was_at_floor = scaler_->at_floor();
    // A replica built from a snapshot (a tracer's first frame, or one that fell behind) costs
    // its tracer a scene build once (30-40 ms at builtin:default): learnt as the fixed part of
    // every frame, it sent the first frames to the quality floor for ten frames or more. The
    // render time still says how fast the farm renders.
    double render_ms = 0.0, one_time_ms = 0.0;
    for (const TracerFrameStats& t : outcome.tracers) {
        render_ms = std::max(render_ms, t.render_ms);
        if (t.from_snapshot) one_time_ms = std::max(one_time_ms, t.update_ms);
    }
    scaler_->observe(std::max(render_ms, frame_ms - one_time_ms), render_ms);
    if (scaler_->at_floor() && !was_at_floor)
        spdlog::warn(
            "workload scaling: at the quality floor ({} spp, roulette {}, {:.0f}% size) and "
            "still slower than {} frames/s",
            scaler_->level().spp, scaler_->level().rr_scale, 100.0 * scaler_->level().resolution,
            target_fps());
    else if (!scaler_->at_floor() && was_at_floor)
        spdlog::info("workload scaling: above the quality floor again");
}

// Hands the frame to the display thread (FrameDisplay) with what it needs of this frame's state.
void Farm::display(PreparedFrame& p, FrameOutcome outcome, double frame_ms, bool rendered) {
    display_.submit({work_, std::move(p.view), std::move(outcome), rendered, frame_ms,
                     tracers_.size(), p.plain_bytes, scaler_ && scaler_->at_floor()});
}

void Farm::log_rate(uint64_t frame, int completed) {  // one stats line a second
    const double now = run_clock_.seconds();
    if (now - last_line_s_ < 1.0) return;
    spdlog::info("frame {}: {:.1f} frames/s, {} tracer(s), {} client(s)", frame,
                 (completed - completed_at_last_line_) / (now - last_line_s_), tracers_.size(),
                 clients_.size());
    last_line_s_ = now;
    completed_at_last_line_ = completed;
}

Status Farm::run(const std::atomic<bool>& stop) {
    if (!o_.dump_frames.empty())
        if (Status s = create_output_folder("--dump-frames", o_.dump_frames); !s) return s;
    net::NetService net;
    if (Status s = listen(net); !s) return s;
    if (!o_.fixed_spp)
        scaler_.emplace(ScalerOptions{target_fps(), o_.spp, o_.min_rr_scale, o_.min_resolution,
                                      o_.render_budget});
    Pacer pacer(target_fps());
    PreparedFrame next = prepare(0);
    const Timer clock;
    int completed = 0;
    for (uint64_t f = 0; (o_.frames == 0 || f < uint64_t(o_.frames)) && !stop; ++f) {
        // The frame's quality level and extra-sample plan need nothing the pacer's wait brings
        // (the level is the last frame's, the plan reads frame f - 2's history): planned
        // before it, off the way from an input to the tracers (0.67 ms p50 in the demo).
        FrameWork work = next_work(f);
        double prepare_ms = 0.0;  // real time: this frame's, on the way from input to tracers
        if (scaler_) {            // paced: prepared now, after the wait, with the newest input
            pacer.wait();
            const Timer preparing;
            if (f > 0) next = prepare(f);
            prepare_ms = preparing.milliseconds();
        }
        const bool skip = converged_and_unchanged(next);
        if (!tracers_.wait_for(f == 0 ? std::size_t(std::max(1, o_.min_tracers)) : 1, stop)) break;
        Timer stage;
        begin_frame(std::move(work), next, !skip);
        const double send_ms = stage.milliseconds();
        const Timer frame_timer;
        PreparedFrame current = std::move(next);
        stage.reset();
        if (!scaler_) next = prepare(f + 1);  // pipelined: N+1's commit while N renders
        if (skip) {
            display(current, FrameOutcome{}, 0.0, false);
            ++completed;
            continue;
        }
        const double prepare_next_ms = stage.milliseconds();
        stage.reset();
        const TracerPool::Wait end = tracers_.wait_for_frame(stop);
        if (end != TracerPool::Wait::complete) continue;
        const double wait_ms = stage.milliseconds(), frame_ms = frame_timer.milliseconds();
        stage.reset();
        FrameOutcome outcome = tracers_.finish();
        observe_frame_time(frame_ms, outcome);
        display(current, std::move(outcome), frame_ms, true);
        stages_.row(f, send_ms, prepare_next_ms, wait_ms, stage.milliseconds(), prepare_ms);
        log_rate(f, ++completed);
    }
    std::printf("frames=%d seconds=%.3f fps=%.2f\n", completed, clock.seconds(),
                completed / clock.seconds());
    std::fflush(stdout);
    shut_down();
    return {};
}

// Sessions must not outlive the NetService (and its io_context) of run(): close them, and let
// the writers flush what is queued (the last frame to clients) for at most two seconds.
void Farm::shut_down() {
    display_.finish();  // the last frames to the clients' queues first
    if (web_) web_->stop();
    std::vector<std::shared_ptr<net::Session>> sessions = tracers_.stop_accepting();
    for (auto& s : clients_.stop_accepting())
        sessions.push_back(std::move(s));
    for (auto& s : sessions)
        s->close("coordinator finished");
    const auto deadline = Clock::now() + std::chrono::seconds(2);
    while (Clock::now() < deadline &&
           std::any_of(sessions.begin(), sessions.end(), [](const auto& s) { return s->open(); }))
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

}  // namespace

Status run_farm(SceneModel scene, const FarmOptions& options, const std::atomic<bool>& stop) {
    if (Status s = check_farm_options(options); !s) return s;
    auto balancer = make_balancer(options.balancer, 0.25, options.speed_smoothing);
    if (!balancer)
        return make_error(ErrorCode::invalid_argument, "--balancer {}: unknown scheme",
                          options.balancer);
    const Camera framing =
        frame_bounds(world_bounds(scene), float(options.width) / float(options.height));
    Farm farm(std::move(scene), options, std::move(balancer), framing);
    if (Status s = farm.start_game(); !s) return s;
    return farm.run(stop);
}

}  // namespace pathfarm::coord
