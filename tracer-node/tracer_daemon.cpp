// Tracer daemon: a network thread delivers envelopes into a queue; this thread applies
// commits and renders, so rendering never blocks the connection.
#include "tracer-node/tracer_daemon.h"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>

#include "common/base/timer.h"
#include "common/film/float_codec.h"
#include "common/net/framing.h"
#include "common/net/session.h"
#include "common/sampling/rng.h"
#include "pathfarm/wire/v1/envelope.pb.h"
#include "tracer-node/backend/render_backend.h"
#include "tracer-node/replica/replica.h"

namespace pathfarm::tracer {
namespace {

namespace pb = ::pathfarm::wire::v1;

// Envelopes from the network thread (parsed there), whether the session is gone, and the
// newest commit announced, so a render of an older frame can be abandoned.
class Inbox {
public:
    void push(std::string bytes) {
        auto e = std::make_unique<pb::Envelope>();
        const bool ok = e->ParseFromString(bytes);
        std::lock_guard lock(mutex_);
        if (!ok) e.reset();  // handled as malformed by the worker
        if (e && e->has_commit())
            newest_commit_ = std::max(newest_commit_.load(), e->commit().frame());
        if (e && e->has_assignment() && e->assignment().truncate_at() > 0) {
            // Control, not work: the render in progress must see it now, not after it ends.
            const uint64_t frame = e->assignment().frame();
            if (frame != truncation_frame_) truncations_.clear();
            truncation_frame_ = frame;
            truncations_.push_back(e->assignment().truncate_at());
            return;
        }
        queue_.push_back(std::move(e));
        cv_.notify_one();
    }
    void close() {
        std::lock_guard lock(mutex_);
        closed_ = true;
        cv_.notify_one();
    }
    // Next envelope (nullptr if it did not parse); nullopt when the session closed (after
    // draining) or stop was requested.
    std::optional<std::unique_ptr<pb::Envelope>> pop(const std::atomic<bool>& stop) {
        std::unique_lock lock(mutex_);
        while (queue_.empty() && !closed_ && !stop)
            cv_.wait_for(lock, std::chrono::milliseconds(100));
        if (queue_.empty()) return std::nullopt;
        auto e = std::move(queue_.front());
        queue_.pop_front();
        return e;
    }
    uint64_t newest_commit() const { return newest_commit_; }
    // Whether row y of the assignment [a.y0, a.y1) of its frame went to another tracer.
    bool truncated(const pb::FrameAssignment& a, uint32_t y) const {
        std::lock_guard lock(mutex_);
        if (a.frame() != truncation_frame_) return false;
        return std::any_of(truncations_.begin(), truncations_.end(),
                           [&](uint32_t at) { return a.y0() < at && at < a.y1() && at <= y; });
    }

private:
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<std::unique_ptr<pb::Envelope>> queue_;
    std::atomic<uint64_t> newest_commit_{0};
    uint64_t truncation_frame_ = 0;
    std::vector<uint32_t> truncations_;  // rows where this frame's assignments now end
    bool closed_ = false;
};

class Worker {
public:
    Worker(const TracerOptions& o, RenderBackend& backend, net::Session& session,
           const Inbox& inbox)
        : options_(o), backend_(backend), session_(session), inbox_(inbox) {}

    // Handles one envelope; an error means the session must be dropped and re-synchronised.
    Status handle(const pb::Envelope* e) {
        if (e == nullptr)
            return make_error(ErrorCode::parse_error, "malformed envelope from the coordinator");
        if (e->has_chunk()) {
            replica_.add_chunk(e->chunk().frame(), e->chunk().SerializeAsString());
            return {};
        }
        if (e->has_commit())
            return replica_.apply(e->commit().SerializeAsString(), e->commit().frame());
        if (e->has_assignment()) return render(e->assignment());
        return {};  // other messages are not for tracers
    }

private:
    Status render(const pb::FrameAssignment& a) {
        if (!replica_.initialised() || a.commit() != replica_.commit())
            return make_error(ErrorCode::invalid_argument,
                              "assignment for commit {} but the replica holds {}", a.commit(),
                              replica_.commit());
        if (a.y1() > a.height() || a.y0() >= a.y1() || a.width() == 0 || a.width() > 16384 ||
            a.height() > 16384)
            return make_error(ErrorCode::invalid_argument, "bad assignment rows [{}, {}) of {}x{}",
                              a.y0(), a.y1(), a.width(), a.height());
        if (replica_.scene_changed()) {
            scene_ = replica_.take_scene_model();
            // Camera-relative, as pathfarm-render does (scene_model.h): same floats, same image.
            recentre_on_camera(scene_, scene_.cameras.empty() ? Camera{} : scene_.cameras[0]);
            if (backend_.wants_bvh_nodes()) backend_.provide_mesh_bvhs(mesh_bvhs());
            if (Status s = backend_.set_scene(scene_); !s) return s;
        }
        RenderJob job;
        job.frame = FrameSpec{int(a.width()),
                              int(a.height()),
                              uint32_t(a.frame()),
                              a.seed(),
                              int(a.spp()),
                              0,
                              scene_.cameras.empty() ? Camera{} : scene_.cameras[0]};
        job.integrator.max_depth = int(a.max_depth());
        job.integrator.rr_scale = a.rr_scale() > 0.0f ? std::min(1.0f, a.rr_scale()) : 1.0f;
        const int tile_rows = kRowsPerWorkUnit * kUnitsPerTile;
        for (int y = int(a.y0()); y < int(a.y1()); y += tile_rows) {
            if (inbox_.newest_commit() > a.commit())
                return {};  // the frame closed: do not finish stale rows
            if (inbox_.truncated(a, uint32_t(y))) return {};  // the rest went to another tracer
            if (Status s = render_tile(a, job, y, std::min(int(a.y1()), y + tile_rows)); !s)
                return s;
        }
        return {};
    }

    // The coordinator's mesh BVHs in SceneModel mesh order (to_scene_model keeps id order).
    std::vector<MeshBvhView> mesh_bvhs() const {
        std::vector<MeshBvhView> views;
        const ReplicaState& state = replica_.state();
        for (const auto& [id, mesh] : state.scene.meshes) {
            const auto it = state.bvh.meshes.find(id);
            views.push_back(it == state.bvh.meshes.end()
                                ? MeshBvhView{}
                                : MeshBvhView{&it->second.nodes, &it->second.prim_indices});
        }
        return views;
    }

    Status render_tile(const pb::FrameAssignment& a, RenderJob& job, int y0, int y1) {
        std::vector<float> rgb(std::size_t(y1 - y0) * a.width() * 3);
        pb::Envelope e;
        pb::Tile* tile = e.mutable_tile();
        const Timer tile_timer;
        const double slowdown = frame_slowdown(options_, a.frame());
        for (int y = y0; y < y1; y += kRowsPerWorkUnit) {        // one work unit at a time, timed
            if (inbox_.newest_commit() > a.commit()) return {};  // the frame closed meanwhile
            if (inbox_.truncated(a, uint32_t(y))) {  // send what is done; the rest went elsewhere
                y1 = y;
                break;
            }
            job.y0 = y;
            job.y1 = std::min(y1, y + kRowsPerWorkUnit);
            const Timer unit;
            auto stats =
                backend_.render_rows(job, rgb.data() + std::size_t(y - y0) * a.width() * 3);
            if (!stats) return stats.error();
            const double unit_s = unit.seconds();
            if (slowdown > 1.0)  // an X times slower machine, unit by unit
                std::this_thread::sleep_for(
                    std::chrono::duration<double>((slowdown - 1.0) * unit_s));
            tile->add_unit_cost_us(uint32_t(unit_s * 1e6));
            tile->add_unit_rays(stats->counters.rays);
        }
        if (y1 == y0) return {};
        rgb.resize(std::size_t(y1 - y0) * a.width() * 3);
        e.set_version(net::kProtocolVersion);
        tile->set_frame(a.frame());
        tile->set_commit(a.commit());
        tile->set_y0(uint32_t(y0));
        tile->set_y1(uint32_t(y1));
        tile->set_raw_bytes(uint32_t(rgb.size() * sizeof(float)));
        tile->set_rgb_zstd(compress_floats(rgb.data(), rgb.size()));
        tile->set_render_ms(tile_timer.milliseconds());
        session_.send(e.SerializeAsString());
        return {};
    }

    const TracerOptions& options_;
    RenderBackend& backend_;
    net::Session& session_;
    const Inbox& inbox_;
    Replica replica_;
    SceneModel scene_;  // what the backend renders; outlives its use by the backend
};

// One connection's lifetime: messages until it closes or the replica needs a fresh snapshot.
void serve_session(const TracerOptions& o, RenderBackend& backend, net::Session& session,
                   Inbox& inbox, const std::atomic<bool>& stop) {
    Worker worker(o, backend, session, inbox);
    while (auto message = inbox.pop(stop)) {
        if (Status s = worker.handle(message->get()); !s) {
            spdlog::error("{}; reconnecting for a fresh snapshot", s.error().message);
            break;
        }
    }
    session.close("tracer stopping");
}

}  // namespace

double frame_slowdown(const TracerOptions& o, uint64_t frame) {
    Pcg32 rng(frame, o.hiccup_seed);
    return rng.next_float() < o.hiccup_p ? 2.0 * o.slowdown : o.slowdown;
}

Status run_tracer(const TracerOptions& o, const std::atomic<bool>& stop) {
    auto kind = parse_backend_kind(o.backend);
    if (!kind) return kind.error();
    auto backend = create_backend(*kind, BackendOptions{o.threads, o.cl_platform, o.cl_device});
    if (!backend) return backend.error();
    if (!(o.slowdown >= 1.0))
        return make_error(ErrorCode::invalid_argument, "--slowdown {}: must be >= 1", o.slowdown);
    if (!(o.hiccup_p >= 0.0 && o.hiccup_p <= 1.0))
        return make_error(ErrorCode::invalid_argument, "--hiccup-p {}: must be in [0, 1]",
                          o.hiccup_p);
    net::NetService net;
    net::ClientConfig config;
    config.host = o.host;
    config.port = o.port;
    config.secret = o.secret;
    config.hello.role = net::PeerRole::tracer;
    config.hello.name = o.name;
    config.hello.backend = o.backend;
    config.hello.threads = uint32_t(o.threads);
    config.hello.wants_bvh_nodes = (*backend)->wants_bvh_nodes();
    auto backoff = std::chrono::milliseconds(200);
    for (int attempt = 0; !stop && (o.max_reconnects < 0 || attempt <= o.max_reconnects);
         ++attempt) {
        auto inbox = std::make_shared<Inbox>();  // handlers go in before the first message
        config.on_message = [inbox](std::string&& m) { inbox->push(std::move(m)); };
        config.on_closed = [inbox](const std::string& reason) {
            spdlog::warn("coordinator connection closed: {}", reason);
            inbox->close();
        };
        auto session = net.connect_sync(config);
        if (!session) {
            spdlog::warn("{} (retrying in {} ms)", session.error().message, backoff.count());
            for (auto waited = std::chrono::milliseconds(0); waited < backoff && !stop;
                 waited += std::chrono::milliseconds(50))
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
            backoff = std::min(backoff * 2, std::chrono::milliseconds(5000));
            continue;
        }
        spdlog::info("connected to {}:{} as \"{}\"", o.host, o.port, o.name);
        backoff = std::chrono::milliseconds(200);
        serve_session(o, **backend, **session, *inbox, stop);
    }
    return {};
}

}  // namespace pathfarm::tracer
