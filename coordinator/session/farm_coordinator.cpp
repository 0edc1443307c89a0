// The farm frame loop. The network thread only records tiles, inputs and membership under
// the mutex; this thread advances the game, talks to tracers and assembles frames.
#include "coordinator/session/farm_coordinator.h"

#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include <spdlog/spdlog.h>

#include "common/base/timer.h"
#include "common/commit/commit_codec.h"
#include "common/film/float_codec.h"
#include "common/film/image_io.h"
#include "common/film/resample.h"
#include "common/net/framing.h"
#include "common/net/session.h"
#include "coordinator/accel/accel_updater.h"
#include "coordinator/balance/balancer.h"
#include "coordinator/balance/row_range.h"
#include "coordinator/commit/bvh_ops.h"
#include "coordinator/commit/commit_builder.h"
#include "coordinator/converge/temporal_accumulator.h"
#include "coordinator/frame/frame_assembler.h"
#include "coordinator/frame/frame_encoder.h"
#include "coordinator/game/game.h"
#include "coordinator/pacing/workload_scaler.h"
#include "coordinator/query/ray_query.h"
#include "coordinator/scene_graph/scene_graph.h"
#include "pathfarm/wire/v1/envelope.pb.h"

namespace pathfarm::coord {
namespace {

namespace pb = ::pathfarm::wire::v1;
using Clock = std::chrono::steady_clock;

// An Envelope holding an already-serialised message in field `field`: protobuf's encoding of
// an embedded message is its tag, its length and its bytes, so no re-parse is needed.
std::string envelope_with(int field, const std::string& message) {
    pb::Envelope head;
    head.set_version(net::kProtocolVersion);
    std::string out = head.SerializeAsString();
    out.push_back(char((field << 3) | 2));
    for (std::size_t n = message.size();; n >>= 7) {
        out.push_back(char((n & 0x7f) | (n >= 0x80 ? 0x80 : 0)));
        if (n < 0x80) break;
    }
    return out + message;
}

// A commit as the envelopes to send: chunks first, the Commit message last.
std::vector<std::string> commit_envelopes(const EncodedCommit& e) {
    std::vector<std::string> out;
    for (const std::string& c : e.chunks)
        out.push_back(envelope_with(pb::Envelope::kChunkFieldNumber, c));
    out.push_back(envelope_with(pb::Envelope::kCommitFieldNumber, e.commit));
    return out;
}

struct TracerState {
    std::shared_ptr<net::Session> session;
    std::string name;
    bool wants_bvh = false;
    std::optional<uint64_t> replica_commit;  // the commit its replica holds once our sends arrive
    std::vector<RowRange> assigned;          // this frame
    RowRange first_assignment;
    double render_ms = 0.0;
    std::optional<uint64_t> measured_frame;  // the frame `measured` describes
    TracerFrame measured;                    // what it rendered and how long it took
};

struct ClientState {
    std::shared_ptr<net::Session> session;
    FrameCodec codec = FrameCodec::png;
};

// Frame N's commit in both forms (with BVH ops for tracers that asked), and what converging
// needs to know about the frame.
struct PreparedFrame {
    uint64_t frame = 0;
    std::vector<std::string> plain, with_bvh;
    std::size_t plain_bytes = 0;
    std::shared_ptr<const AccelSnapshot> accel;
    FrameView view;                    // camera, instances, deformed, cut (G-buffer added later)
    uint64_t last_input_sequence = 0;  // the newest input applied in this frame
    bool unchanged = false;            // nothing in the scene changed since the last frame
};

// Frame size and quality of the frame being rendered (workload scaling changes them).
struct FrameQuality {
    int width = 0, height = 0, spp = 1;
    float rr_scale = 1.0f;
};

class Farm {
public:
    Farm(SceneModel scene, const FarmOptions& o)
        : o_(o),
          scene_name_(scene.name),
          default_camera_(default_camera(scene, o)),
          graph_(std::move(scene)) {
        if (o.clip) graph_.set_playing_clip(*o.clip);
        // A scene without a camera is framed from its bounds (DESIGN.md), as pathfarm-render
        // frames it, and the replicas get that camera like any other.
        if (graph_.state().cameras.empty()) graph_.set_camera(std::nullopt, default_camera_, true);
        RenderSettings s = graph_.state().settings;
        s.width = o.width;
        s.height = o.height;
        s.spp = o.spp;
        s.max_depth = o.max_depth;
        s.seed = o.seed;
        graph_.set_settings(s);
    }

    Status run(const std::atomic<bool>& stop);
    double target_fps() const { return o_.target_fps > 0.0 ? o_.target_fps : o_.fps; }
    Status start_game() {
        auto g = make_game(o_.game, scene_name_, graph_);
        if (!g) return g.error();
        game_ = std::move(*g);
        spdlog::info("game: {}", game_->name());
        return {};
    }
    void set_balancer(std::unique_ptr<Balancer> b) {
        steal_ = b->name() == "cost-predictive";
        balancer_ = std::move(b);
    }

private:
    // --- network thread
    void on_tracer(std::shared_ptr<net::Session> s);
    void on_client(std::shared_ptr<net::Session> s);
    void on_tile(uint64_t id, const std::string& bytes);
    void on_tracer_closed(uint64_t id);
    void steal_for(uint64_t id);  // holds mutex_: an idle tracer takes part of another's rows
    std::vector<double> unit_cost_map() const;                                  // holds mutex_
    double delivered_cost(uint64_t id, const std::vector<double>& cost) const;  // holds mutex_
    int delivered_rows(uint64_t id) const;  // holds mutex_: rows of this frame it rendered
    // --- frame loop (callers hold mutex_ where noted)
    PreparedFrame prepare(uint64_t frame);
    void sync_and_assign(const PreparedFrame& p, bool assign_rows);     // holds mutex_
    void reissue(const std::vector<RowRange>& ranges, bool idle_only);  // holds mutex_
    bool wait_for_frame(const std::atomic<bool>& stop);                 // false: abandoned
    void assign(uint64_t id, TracerState& t, const RowRange& r);        // holds mutex_
    void finish_frame(PreparedFrame& p, double frame_ms, bool rendered);
    void account_tracers(double& t_max, double& idle, int& n);  // holds mutex_
    void send_to_clients(const FloatImage& image, const PreparedFrame& p);
    FrameQuality next_quality() const;
    GBuffer frame_gbuffer(const PreparedFrame& p);

    static Camera default_camera(const SceneModel& scene, const FarmOptions& o) {
        return frame_bounds(world_bounds(scene), float(o.width) / float(o.height));
    }

    FarmOptions o_;
    std::string scene_name_;
    Camera default_camera_;
    SceneGraph graph_;
    std::unique_ptr<Game> game_;
    RayQueryService queries_;
    TemporalAccumulator accumulator_;
    FrameQuality q_;                        // of frame_
    std::optional<WorkloadScaler> scaler_;  // none with --fixed-spp
    Timer run_clock_;                       // since the farm started: stats' wall_ms
    bool stopping_ = false;                 // holds mutex_: run() is closing the sessions
    struct TracedGBuffer {                  // the last frame's, to update instead of re-trace
        GBuffer gbuffer;
        std::shared_ptr<const AccelSnapshot> accel;
        Camera camera;
    };
    std::optional<TracedGBuffer> last_gbuffer_;
    AccelUpdater accel_;
    std::shared_ptr<const AccelSnapshot> accel_snapshot_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::map<uint64_t, TracerState> tracers_;
    std::map<uint64_t, ClientState> clients_;
    std::optional<FrameAssembler> assembler_;
    uint64_t frame_ = 0;
    std::size_t tile_bytes_ = 0;
    std::unique_ptr<Balancer> balancer_;
    bool steal_ = false;  // idle tracers take rows of the busiest (the cost-predictive scheme)
    std::vector<double> unit_rays_, unit_us_, last_unit_cost_;  // per work unit, this / last frame
    std::vector<uint64_t> unit_owner_;  // who delivered each unit (session ids; 0: nobody yet)
    std::vector<PlayerInput> pending_inputs_;  // received, applied at the next frame boundary
    uint64_t last_applied_input_ = 0;
    std::ofstream stats_, tracer_stats_, stages_, costs_;
};

void Farm::on_tracer(std::shared_ptr<net::Session> s) {
    const uint64_t id = s->peer().session_id;
    s->on_message = [this, id](std::string&& m) { on_tile(id, m); };
    s->on_closed = [this, id](const std::string&) { on_tracer_closed(id); };
    std::lock_guard lock(mutex_);
    if (stopping_) return s->close("coordinator finishing");
    TracerState t;
    t.session = s;
    t.name = s->peer().name;
    t.wants_bvh = s->peer().wants_bvh_nodes;
    tracers_[id] = std::move(t);
    cv_.notify_all();
}

void Farm::on_client(std::shared_ptr<net::Session> s) {
    const uint64_t id = s->peer().session_id;
    s->on_message = [this, id, weak = std::weak_ptr<net::Session>(s)](std::string&& m) {
        pb::Envelope e;
        if (!e.ParseFromString(m) || !e.has_input()) {
            if (auto session = weak.lock())
                session->reject(net::ProtocolError::out_of_order, "clients send InputEvent only");
            return;
        }
        const pb::InputEvent& in = e.input();
        PlayerInput input;
        input.sequence = in.sequence();
        input.action = in.action();
        if (in.camera_to_world().size() == sizeof(Mat4)) {
            Mat4 m4;
            std::memcpy(&m4[0][0], in.camera_to_world().data(), sizeof(Mat4));
            const float* v = &m4[0][0];
            if (std::all_of(v, v + 16, [](float x) { return std::isfinite(x); }))
                input.camera_to_world = m4;  // a pose with NaN/Inf is ignored, not rendered
        }
        // A client's move is bounded: at most 10 m and half a turn per input (NaN: none).
        for (int k = 0; k < std::min(in.move_size(), 5); ++k) {
            const float limit = k < 3 ? 10.0f : 3.14159265f;
            input.move[std::size_t(k)] =
                std::isfinite(in.move(k)) ? std::clamp(in.move(k), -limit, limit) : 0.0f;
        }
        std::lock_guard lock(mutex_);
        pending_inputs_.push_back(input);
    };
    s->on_closed = [this, id](const std::string& reason) {
        spdlog::info("client {} left: {}", id, reason);
        std::lock_guard lock(mutex_);
        clients_.erase(id);
    };
    std::lock_guard lock(mutex_);
    if (stopping_) return s->close("coordinator finishing");
    clients_[id] = ClientState{s, choose_codec(s->peer().codecs)};
}

void Farm::on_tile(uint64_t id, const std::string& bytes) {
    pb::Envelope e;
    std::lock_guard lock(mutex_);
    const auto it = tracers_.find(id);
    if (it == tracers_.end()) return;
    if (!e.ParseFromString(bytes) || !e.has_tile()) {
        it->second.session->reject(net::ProtocolError::out_of_order, "tracers send Tile only");
        return;
    }
    const pb::Tile& t = e.tile();
    if (!assembler_ || t.frame() != frame_) return;  // a tile of a frame already closed
    const RowRange range{int(t.y0()), int(t.y1())};
    const std::size_t floats = std::size_t(std::max(0, range.rows())) * std::size_t(q_.width) * 3;
    auto rgb = decompress_floats(t.rgb_zstd(), floats);
    if (range.empty() || range.y1 > q_.height || !rgb) {
        it->second.session->reject(net::ProtocolError::malformed,
                                   "tile rows or pixels do not fit the frame");
        return;
    }
    assembler_->add(range, rgb->data());
    it->second.render_ms += t.render_ms();
    if (steal_ && !assembler_->complete()) steal_for(id);
    const std::size_t unit0 = std::size_t(range.y0 / kRowsPerWorkUnit);
    for (int k = 0; k < t.unit_rays_size() && unit0 + std::size_t(k) < unit_rays_.size(); ++k)
        unit_rays_[unit0 + std::size_t(k)] = double(t.unit_rays(k));
    for (int k = 0; k < t.unit_cost_us_size() && unit0 + std::size_t(k) < unit_us_.size(); ++k) {
        unit_us_[unit0 + std::size_t(k)] = double(t.unit_cost_us(k));
        unit_owner_[unit0 + std::size_t(k)] = id;
    }
    tile_bytes_ += bytes.size();
    cv_.notify_all();
}

// Last frame's per-unit cost in one tracer-independent scale: each unit's measured time (which
// sees what its rays cost to shade) times the rays per microsecond of the tracer that rendered
// it (which removes that tracer's speed).
std::vector<double> Farm::unit_cost_map() const {
    std::map<uint64_t, std::pair<double, double>> per_tracer;  // rays, us
    for (std::size_t u = 0; u < unit_us_.size(); ++u) {
        per_tracer[unit_owner_[u]].first += unit_rays_[u];
        per_tracer[unit_owner_[u]].second += unit_us_[u];
    }
    std::vector<double> cost(unit_us_.size());
    for (std::size_t u = 0; u < cost.size(); ++u) {
        const auto& [rays, us] = per_tracer[unit_owner_[u]];
        cost[u] = us > 0.0 ? unit_us_[u] * rays / us : unit_rays_[u];
    }
    return cost;
}

int Farm::delivered_rows(uint64_t id) const {
    int rows = 0;
    for (std::size_t u = 0; u < unit_owner_.size(); ++u)
        if (unit_owner_[u] == id)
            rows += std::min(q_.height, int(u + 1) * kRowsPerWorkUnit) - int(u) * kRowsPerWorkUnit;
    return rows;
}

double Farm::delivered_cost(uint64_t id, const std::vector<double>& cost) const {
    double sum = 0.0;
    for (std::size_t u = 0; u < cost.size(); ++u)
        if (unit_owner_[u] == id) sum += cost[u];
    return sum;
}

void Farm::steal_for(uint64_t id) {
    TracerState& me = tracers_.at(id);
    for (const RowRange& r : me.assigned)
        if (!assembler_->missing(r).empty()) return;  // still busy with its own rows
    // The tracer with the most rows still missing gives up the tail half of its last gap.
    std::optional<RowRange> gap;
    uint64_t victim = 0;
    int most = 0;
    for (const auto& [other, t] : tracers_) {
        if (other == id || t.replica_commit != frame_) continue;
        int missing = 0;
        std::optional<RowRange> last;
        for (const RowRange& r : t.assigned)
            for (const RowRange& m : assembler_->missing(r)) {
                missing += m.rows();
                last = m;
            }
        if (missing > most) {
            most = missing;
            gap = last;
            victim = other;
        }
    }
    // One unit is probably being rendered already; taking less than two is not worth a message.
    if (!gap || gap->rows() < 2 * kRowsPerWorkUnit) return;
    const int units = (gap->rows() / kRowsPerWorkUnit) / 2;
    const int y0 = std::max(gap->y0, gap->y1 - units * kRowsPerWorkUnit);
    const RowRange tail{y0 - y0 % kRowsPerWorkUnit, gap->y1};
    assign(id, me, tail);
    // The victim stops before the tail instead of rendering it too; its rows end there now.
    TracerState& v = tracers_.at(victim);
    for (RowRange& r : v.assigned)
        if (r.y0 < tail.y0 && tail.y0 < r.y1) r.y1 = tail.y0;
    pb::Envelope e;
    e.set_version(net::kProtocolVersion);
    e.mutable_assignment()->set_frame(frame_);
    e.mutable_assignment()->set_commit(frame_);
    e.mutable_assignment()->set_truncate_at(uint32_t(tail.y0));
    v.session->send(e.SerializeAsString());
}

void Farm::on_tracer_closed(uint64_t id) {
    std::lock_guard lock(mutex_);
    const auto it = tracers_.find(id);
    if (it == tracers_.end()) return;
    spdlog::warn("tracer \"{}\" left", it->second.name);
    const std::vector<RowRange> owned = it->second.assigned;
    tracers_.erase(it);
    if (!assembler_) return;
    std::vector<RowRange> lost;  // its rows that never arrived go to the others now
    for (const RowRange& r : owned)
        for (const RowRange& m : assembler_->missing(r))
            lost.push_back(m);
    reissue(lost, false);
    cv_.notify_all();
}

PreparedFrame Farm::prepare(uint64_t frame) {
    std::vector<PlayerInput> inputs;
    {
        std::lock_guard lock(mutex_);  // input takes effect at frame boundaries
        inputs.swap(pending_inputs_);
    }
    const double clock = double(frame) / o_.fps;  // the fixed game clock (DESIGN.md, "Time")
    for (const PlayerInput& in : inputs) {
        game_->on_input(in, clock, graph_, queries_);
        last_applied_input_ = std::max(last_applied_input_, in.sequence);
    }
    game_->update(clock, graph_);
    graph_.advance(clock);
    const ChangeSet changes = graph_.take_changes();
    const auto previous = accel_snapshot_;
    accel_snapshot_ = frame == 0 ? accel_.build(graph_.state(), frame)
                                 : accel_.update(graph_.state(), changes, frame);
    queries_.publish(accel_snapshot_);
    PreparedFrame p;
    p.frame = frame;
    p.unchanged = frame > 0 && changes.empty();
    p.accel = accel_snapshot_;
    p.last_input_sequence = last_applied_input_;
    const SceneState& state = graph_.state();
    if (const auto cam = state.cameras.find(state.active_camera); cam != state.cameras.end())
        p.view.camera = cam->second;
    for (const InstanceAccel& inst : accel_snapshot_->instances)
        p.view.instances[inst.id] = inst.to_world;
    for (const auto& [id, inst] : state.instances)
        if (changes.vertices_changed.count(inst.mesh)) p.view.deformed.insert(id);
    // What lights the scene changed: history of every pixel is wrong.
    p.view.cut = !changes.materials_set.empty() || !changes.materials_removed.empty() ||
                 !changes.textures_set.empty() || changes.environment;
    Commit commit = build_commit(state, changes, frame, frame == 0 ? 0 : frame - 1);
    const EncodedCommit plain = encode_commit(commit);
    p.plain_bytes = plain.total_bytes();
    p.plain = commit_envelopes(plain);
    for (CommitOp& op : build_bvh_ops(previous.get(), *accel_snapshot_))
        commit.ops.push_back(std::move(op));
    p.with_bvh = commit_envelopes(encode_commit(commit));
    return p;
}

void Farm::assign(uint64_t id, TracerState& t, const RowRange& r) {
    pb::Envelope e;
    e.set_version(net::kProtocolVersion);
    auto* a = e.mutable_assignment();
    a->set_frame(frame_);
    a->set_commit(frame_);
    a->set_y0(uint32_t(r.y0));
    a->set_y1(uint32_t(r.y1));
    a->set_width(uint32_t(q_.width));
    a->set_height(uint32_t(q_.height));
    a->set_spp(uint32_t(q_.spp));
    a->set_seed(o_.seed);
    a->set_max_depth(uint32_t(o_.max_depth));
    if (q_.rr_scale < 1.0f) a->set_rr_scale(q_.rr_scale);
    t.session->send(e.SerializeAsString());
    t.assigned.push_back(r);
    spdlog::debug("frame {}: rows [{}, {}) to tracer {} \"{}\"", frame_, r.y0, r.y1, id, t.name);
}

void Farm::sync_and_assign(const PreparedFrame& p, bool assign_rows) {
    std::optional<std::vector<std::string>> snapshot, snapshot_bvh;  // made once, if needed
    std::vector<uint64_t> synced;
    for (auto& [id, t] : tracers_) {
        const bool current = p.frame > 0 && t.replica_commit == p.frame - 1;
        const std::vector<std::string>* messages = t.wants_bvh ? &p.with_bvh : &p.plain;
        if (!current) {
            auto& snap = t.wants_bvh ? snapshot_bvh : snapshot;
            if (!snap) {
                Commit c = make_snapshot(graph_.state(), p.frame);
                if (t.wants_bvh)
                    for (CommitOp& op : build_bvh_ops(nullptr, *accel_snapshot_))
                        c.ops.push_back(std::move(op));
                snap = commit_envelopes(encode_commit(c));
            }
            messages = &*snap;
        }
        for (const std::string& m : *messages)
            t.session->send(m);
        t.replica_commit = p.frame;
        t.assigned.clear();
        t.render_ms = 0.0;
        synced.push_back(id);
    }
    if (!assign_rows) return;  // replicas follow the (empty) commit; nothing to render
    // A new render size makes last frame's rows and unit costs meaningless: start even.
    const bool resized = last_unit_cost_.size() != unit_rays_.size();
    BalanceInput in{q_.height, {}, resized ? std::vector<double>{} : last_unit_cost_};
    for (uint64_t id : synced) {  // tracers that did not render the previous frame are new to it
        const TracerState& t = tracers_.at(id);
        in.last.push_back(!resized && p.frame > 0 && t.measured_frame == p.frame - 1
                              ? t.measured
                              : TracerFrame{});
    }
    const auto ranges = balancer_->assign(in);
    for (std::size_t i = 0; i < synced.size(); ++i) {
        TracerState& t = tracers_.at(synced[i]);
        t.first_assignment = ranges[i];
        if (!ranges[i].empty()) assign(synced[i], t, ranges[i]);
    }
}

void Farm::reissue(const std::vector<RowRange>& ranges, bool idle_only) {
    std::vector<uint64_t> targets;
    for (auto& [id, t] : tracers_) {
        if (t.replica_commit != frame_) continue;  // joined mid-frame: no replica of this frame
        bool idle = true;
        for (const RowRange& r : t.assigned)
            idle = idle && assembler_->missing(r).empty();
        if (idle || !idle_only) targets.push_back(id);
    }
    if (targets.empty() && idle_only) return reissue(ranges, false);
    if (targets.empty()) return;
    for (const RowRange& range : ranges) {
        const auto parts = split_range(range, int(targets.size()));
        for (std::size_t i = 0; i < parts.size(); ++i)
            if (!parts[i].empty()) assign(targets[i], tracers_.at(targets[i]), parts[i]);
    }
}

bool Farm::wait_for_frame(const std::atomic<bool>& stop) {
    std::unique_lock lock(mutex_);
    auto deadline = Clock::now() + std::chrono::milliseconds(o_.deadline_ms);
    while (!assembler_->complete() && !stop) {
        const bool any_synced = std::any_of(tracers_.begin(), tracers_.end(), [&](const auto& kv) {
            return kv.second.replica_commit == frame_;
        });
        if (!any_synced && !tracers_.empty()) {
            spdlog::warn(
                "frame {}: every tracer of this frame left; continuing with the next frame",
                frame_);
            return false;
        }
        if (cv_.wait_until(lock,
                           std::min(deadline, Clock::now() + std::chrono::milliseconds(100))) ==
                std::cv_status::timeout &&
            Clock::now() >= deadline) {
            const auto missing = assembler_->missing({0, q_.height});
            spdlog::warn("frame {}: {} row ranges missed the {} ms deadline; re-issuing", frame_,
                         missing.size(), o_.deadline_ms);
            reissue(missing, true);
            deadline = Clock::now() + std::chrono::milliseconds(o_.deadline_ms);
        }
    }
    return assembler_->complete();
}

void Farm::finish_frame(PreparedFrame& p, double frame_ms, bool rendered) {
    std::unique_lock lock(mutex_);
    // A frame that rendered nothing (converged, unchanged) shows the converged image again.
    FloatImage image = rendered ? assembler_->image() : accumulator_.output();
    double t_max = 0.0, idle = 0.0;
    int n = 0;
    if (rendered) account_tracers(t_max, idle, n);
    const double idle_pct = n > 0 && t_max > 0.0 ? 100.0 * idle / (n * t_max) : 0.0;
    const std::size_t tracer_count = tracers_.size();
    const std::size_t tile_bytes = tile_bytes_;
    lock.unlock();
    // Display: upscale what workload scaling rendered smaller, then converge.
    const Timer display_timer;
    if (image.width != o_.width || image.height != o_.height)
        image = resize_bilinear(image, o_.width, o_.height);
    ConvergeStats converged{0.0, 1.0, 0.0};
    if (o_.converge && rendered) converged = accumulator_.blend(image, std::move(p.view));
    const double display_ms = display_timer.milliseconds();
    const bool at_floor = scaler_ && scaler_->at_floor();
    if (stats_.is_open())
        stats_ << frame_ << ',' << tracer_count << ',' << frame_ms << ',' << idle_pct << ','
               << p.plain_bytes << ',' << tile_bytes << ',' << (rendered ? q_.spp : 0) << ','
               << q_.rr_scale << ',' << q_.width << ',' << q_.height << ',' << converged.mean_f
               << ',' << converged.kept << ',' << int(at_floor) << ',' << display_ms << ','
               << run_clock_.milliseconds() << '\n';
    stats_.flush();  // live monitoring and tests read these while the farm runs
    tracer_stats_.flush();
    send_to_clients(image, p);
    if (!o_.dump_frames.empty()) {
        const std::string path = fmt::format("{}/frame_{:06d}.pfm", o_.dump_frames, frame_);
        if (Status s = write_image(path, image); !s) spdlog::error("{}", s.error().message);
    }
}

// Per-tracer statistics and the cost model's inputs for the next frame. Holds mutex_.
void Farm::account_tracers(double& t_max, double& idle, int& n) {
    for (const auto& [id, t] : tracers_)
        if (t.replica_commit == frame_ && t.render_ms > 0.0) t_max = std::max(t_max, t.render_ms);
    for (const auto& [id, t] : tracers_) {
        if (t.replica_commit != frame_ || t.render_ms <= 0.0) continue;
        idle += t_max - t.render_ms;
        ++n;
        if (tracer_stats_.is_open())
            tracer_stats_ << frame_ << ',' << t.name << ',' << t.first_assignment.y0 << ','
                          << t.first_assignment.rows() << ',' << t.render_ms << ','
                          << delivered_rows(id) << '\n';
    }
    last_unit_cost_ = unit_cost_map();
    for (auto& [id, t] : tracers_)
        if (t.replica_commit == frame_ && t.render_ms > 0.0) {
            t.measured_frame = frame_;
            t.measured = TracerFrame{t.first_assignment, t.render_ms,
                                     delivered_cost(id, last_unit_cost_) / t.render_ms};
        }
    if (costs_.is_open())
        for (std::size_t u = 0; u < unit_us_.size(); ++u)
            costs_ << frame_ << ',' << u << ',' << unit_us_[u] << '\n';
}

// Encodes `image` once per codec and sends it to every client.
void Farm::send_to_clients(const FloatImage& image, const PreparedFrame& p) {
    std::unique_lock lock(mutex_);
    std::map<FrameCodec, std::string> encoded;
    std::vector<std::pair<std::shared_ptr<net::Session>, FrameCodec>> targets;
    for (auto& [id, c] : clients_)
        targets.emplace_back(c.session, c.codec);
    const uint64_t last_input = p.last_input_sequence;
    lock.unlock();
    for (auto& [session, codec] : targets) {
        if (!encoded.count(codec)) {
            auto bytes = encode_frame(image, codec, o_.jpeg_quality);
            if (!bytes) {
                spdlog::error("frame {}: {}", frame_, bytes.error().message);
                continue;
            }
            pb::Envelope e;
            e.set_version(net::kProtocolVersion);
            auto* f = e.mutable_frame();
            f->set_frame(frame_);
            f->set_width(uint32_t(o_.width));
            f->set_height(uint32_t(o_.height));
            f->set_codec(pb::FrameCodec(int(codec)));
            f->set_data(std::move(*bytes));
            f->set_last_input_sequence(last_input);
            encoded[codec] = e.SerializeAsString();
        }
        session->send(encoded[codec]);
    }
}

// With the same camera as last frame only the pixels under changed instances are traced again.
GBuffer Farm::frame_gbuffer(const PreparedFrame& p) {
    const Camera& cam = p.view.camera;
    const bool reuse = last_gbuffer_ &&
                       last_gbuffer_->camera.camera_to_world == cam.camera_to_world &&
                       last_gbuffer_->camera.yfov_radians == cam.yfov_radians;
    GBuffer g = reuse ? update_gbuffer(last_gbuffer_->gbuffer, *last_gbuffer_->accel, *p.accel, cam)
                      : trace_gbuffer(*p.accel, cam, o_.width, o_.height);
    last_gbuffer_ = TracedGBuffer{g, p.accel, cam};
    return g;
}

FrameQuality Farm::next_quality() const {
    if (!scaler_) return {o_.width, o_.height, o_.spp, 1.0f};
    const QualityLevel& l = scaler_->level();
    return {std::max(8, int(std::lround(o_.width * l.resolution))),
            std::max(8, int(std::lround(o_.height * l.resolution))), l.spp, l.rr_scale};
}

Status Farm::run(const std::atomic<bool>& stop) {
    net::NetService net;
    net::ServerConfig tracer_config{o_.tracer_port,           o_.bind_address,
                                    {net::PeerRole::tracer},  o_.secret,
                                    net::kMaxFromTracerBytes, std::chrono::milliseconds(5000)};
    net::ServerConfig client_config{o_.client_port,           o_.bind_address,
                                    {net::PeerRole::client},  o_.secret,
                                    net::kMaxFromClientBytes, std::chrono::milliseconds(5000)};
    auto tracer_port = net.listen(tracer_config, [this](auto s) { on_tracer(std::move(s)); });
    if (!tracer_port) return tracer_port.error();
    auto client_port = net.listen(client_config, [this](auto s) { on_client(std::move(s)); });
    if (!client_port) return client_port.error();
    std::printf("listening tracer_port=%u client_port=%u\n", unsigned(*tracer_port),
                unsigned(*client_port));
    std::fflush(stdout);
    if (!o_.stats_csv.empty()) {
        stats_.open(o_.stats_csv);
        stats_ << "frame,tracers,frame_ms,idle_pct,commit_bytes,tile_bytes,spp,rr_scale,"
                  "render_width,render_height,f,kept,at_floor,display_ms,wall_ms\n";
    }
    if (!o_.record_costs.empty()) {
        costs_.open(o_.record_costs);
        costs_ << "frame,unit,cost_us\n";
    }
    if (!o_.stages_csv.empty()) {
        stages_.open(o_.stages_csv);
        stages_ << "frame,send_ms,prepare_next_ms,wait_tiles_ms,assemble_and_stream_ms\n";
    }
    if (!o_.tracer_stats_csv.empty()) {
        tracer_stats_.open(o_.tracer_stats_csv);
        tracer_stats_ << "frame,tracer,first_row,rows,render_ms,rows_delivered\n";
    }
    if (!o_.dump_frames.empty()) std::filesystem::create_directories(o_.dump_frames);
    if (!o_.fixed_spp)
        scaler_.emplace(ScalerOptions{target_fps(), o_.spp, o_.min_rr_scale, o_.min_resolution});
    PreparedFrame next = prepare(0);
    const Timer clock;
    // Pacing: with a target frame rate, frame f starts no earlier than one interval after f-1.
    const auto interval = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / target_fps()));
    Clock::time_point next_start = Clock::now();
    int completed = 0, completed_at_last_line = 0;
    double last_line = 0.0;
    for (uint64_t f = 0; (o_.frames == 0 || f < uint64_t(o_.frames)) && !stop; ++f) {
        if (scaler_) {
            std::this_thread::sleep_until(next_start);
            next_start = std::max(Clock::now(), next_start + interval);
            // Paced: the frame is prepared now, after the wait, with the newest input (the
            // pipelined preparation below would add a frame interval of input latency).
            if (f > 0) next = prepare(f);
        }
        // A still, unchanged view whose every pixel has converged renders nothing new.
        const bool skip = o_.converge && o_.converged_frames > 0 && next.unchanged &&
                          accumulator_.min_history_frames() >= float(o_.converged_frames);
        Timer stage;
        {
            std::unique_lock lock(mutex_);
            const std::size_t needed = f == 0 ? std::size_t(std::max(1, o_.min_tracers)) : 1;
            if (tracers_.size() < needed) spdlog::info("waiting for {} tracer(s)", needed);
            cv_.wait(lock, [&] { return tracers_.size() >= needed || stop; });
            if (stop) break;
            frame_ = f;
            q_ = next_quality();
            assembler_.emplace(q_.width, q_.height);
            tile_bytes_ = 0;
            unit_rays_.assign(std::size_t(work_units(q_.height)), 0.0);
            unit_us_.assign(unit_rays_.size(), 0.0);
            unit_owner_.assign(unit_rays_.size(), 0);
            stage.reset();
            sync_and_assign(next, !skip);
        }
        const double send_ms = stage.milliseconds();
        const Timer frame_timer;
        PreparedFrame current = std::move(next);
        stage.reset();
        if (!scaler_) next = prepare(f + 1);  // pipelined: N+1's commit while N renders
        if (skip) {
            finish_frame(current, 0.0, false);
            ++completed;
            continue;
        }
        // The G-buffer for reprojection, traced while the tracers render.
        if (o_.converge) current.view.gbuffer = frame_gbuffer(current);
        const double prepare_ms = stage.milliseconds();
        stage.reset();
        if (!wait_for_frame(stop)) continue;
        const double wait_ms = stage.milliseconds();
        const double frame_ms = frame_timer.milliseconds();
        if (scaler_) {
            const bool was_at_floor = scaler_->at_floor();
            scaler_->observe(frame_ms);
            if (scaler_->at_floor() && !was_at_floor)
                spdlog::warn(
                    "workload scaling: at the quality floor ({} spp, roulette {}, "
                    "{:.0f}% size) and still slower than {} frames/s",
                    scaler_->level().spp, scaler_->level().rr_scale,
                    100.0 * scaler_->level().resolution, target_fps());
            else if (!scaler_->at_floor() && was_at_floor)
                spdlog::info("workload scaling: above the quality floor again");
        }
        stage.reset();
        finish_frame(current, frame_ms, true);
        if (stages_.is_open())
            stages_ << f << ',' << send_ms << ',' << prepare_ms << ',' << wait_ms << ','
                    << stage.milliseconds() << '\n';
        ++completed;
        if (clock.seconds() - last_line >= 1.0) {  // one stats line a second
            std::lock_guard lock(mutex_);
            spdlog::info("frame {}: {:.1f} frames/s, {} tracer(s), {} client(s)", f,
                         (completed - completed_at_last_line) / (clock.seconds() - last_line),
                         tracers_.size(), clients_.size());
            last_line = clock.seconds();
            completed_at_last_line = completed;
        }
    }
    std::printf("frames=%d seconds=%.3f fps=%.2f\n", completed, clock.seconds(),
                completed / clock.seconds());
    std::fflush(stdout);
    // Sessions must not outlive the NetService (and its io_context) declared in this scope.
    std::map<uint64_t, TracerState> tracers;
    std::map<uint64_t, ClientState> clients;
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;  // peers connecting from now on are turned away
        tracers.swap(tracers_);
        clients.swap(clients_);
    }
    for (auto& [id, t] : tracers)
        t.session->close("coordinator finished");
    for (auto& [id, c] : clients)
        c.session->close("coordinator finished");
    // Let the writers flush what is queued (the last frame to clients) before the NetService
    // and its io_context go away with this scope.
    const auto flush_deadline = Clock::now() + std::chrono::seconds(2);
    const auto any_open = [&] {
        return std::any_of(tracers.begin(), tracers.end(),
                           [](const auto& kv) { return kv.second.session->open(); }) ||
               std::any_of(clients.begin(), clients.end(),
                           [](const auto& kv) { return kv.second.session->open(); });
    };
    while (any_open() && Clock::now() < flush_deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return {};
}

}  // namespace

Status run_farm(SceneModel scene, const FarmOptions& options, const std::atomic<bool>& stop) {
    if (options.width <= 0 || options.height <= 0 || options.spp <= 0 || !(options.fps > 0.0) ||
        options.deadline_ms <= 0)
        return make_error(ErrorCode::invalid_argument,
                          "--width/--height/--spp/--fps/--deadline-ms must be positive");
    auto balancer = make_balancer(options.balancer);
    if (!balancer)
        return make_error(ErrorCode::invalid_argument, "--balancer {}: unknown scheme",
                          options.balancer);
    if (options.jpeg_quality < 1 || options.jpeg_quality > 100)
        return make_error(ErrorCode::invalid_argument, "--jpeg-quality {}: must be in [1, 100]",
                          options.jpeg_quality);
    if (!(options.min_rr_scale > 0.0f && options.min_rr_scale <= 1.0f) ||
        !(options.min_resolution > 0.0f && options.min_resolution <= 1.0f) ||
        !(options.target_fps >= 0.0))
        return make_error(
            ErrorCode::invalid_argument,
            "--min-rr-scale and --min-resolution must be in (0, 1], --target-fps >= 0");
    Farm farm(std::move(scene), options);
    farm.set_balancer(std::move(balancer));
    if (Status s = farm.start_game(); !s) return s;
    return farm.run(stop);
}

}  // namespace pathfarm::coord
