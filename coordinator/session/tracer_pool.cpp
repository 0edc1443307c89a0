// The farm's tracers: membership, replica sync, row assignment, tiles, re-issue and stealing.
#include "coordinator/session/tracer_pool.h"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "common/film/float_codec.h"
#include "common/wire/messages.h"
#include "coordinator/balance/row_range.h"
#include "coordinator/balance/steal.h"

namespace pathfarm::coord {

namespace {

// What a steal costs before the thief's rows can arrive: the assignment out, the thief picking
// it up, and its tile back. On loopback the farm logs 0.3-1 ms ("steal overhead", debug).
constexpr double kStealLatencyMs = 1.0;

double ms_between(TracerPool::Clock::time_point a, TracerPool::Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

TracerPool::TracerPool(std::unique_ptr<Balancer> balancer, std::chrono::milliseconds deadline,
                       std::function<Clock::time_point()> now)
    : balancer_(std::move(balancer)), deadline_(deadline), now_(std::move(now)) {}

void TracerPool::add(std::shared_ptr<net::Session> s) {
    const uint64_t id = s->peer().session_id;
    s->on_message = [this, id](std::string&& m) { on_tile(id, m); };
    s->on_closed = [this, id](const std::string&) { on_closed(id); };
    std::lock_guard lock(mutex_);
    if (!accepting_) return s->close("coordinator finishing");
    Tracer t;
    t.session = s;
    t.name = s->peer().name;
    t.wants_bvh = s->peer().wants_bvh_nodes;
    tracers_[id] = std::move(t);
    cv_.notify_all();
}

bool TracerPool::wait_for(std::size_t count, const std::atomic<bool>& stop) {
    std::unique_lock lock(mutex_);
    if (tracers_.size() < count) spdlog::info("waiting for {} tracer(s)", count);
    while (tracers_.size() < count && !stop)
        cv_.wait_for(lock, std::chrono::milliseconds(100));
    return !stop;
}

std::size_t TracerPool::size() const {
    std::lock_guard lock(mutex_);
    return tracers_.size();
}

void TracerPool::begin(const FrameWork& work, const FrameCommit& commit, bool render) {
    std::lock_guard lock(mutex_);
    work_ = work;
    commit_ = FrameCommit{nullptr, nullptr, commit.snapshot, commit.snapshot_during_frame};
    assembler_.emplace(work.width, work.height, work.first_hits);
    tile_bytes_ = 0;
    units_.assign(std::size_t(work_units(work.height)), UnitReport{});
    std::optional<std::vector<std::string>> snapshots[2];  // made once each, if needed
    std::vector<uint64_t> synced;
    for (auto& [id, t] : tracers_) {
        sync(t, commit, snapshots);
        synced.push_back(id);
    }
    if (render) split_rows(synced);
}

void TracerPool::sync(Tracer& t, const FrameCommit& commit,
                      std::optional<std::vector<std::string>> snapshots[2]) {
    const std::vector<std::string>* messages = t.wants_bvh ? commit.with_bvh : commit.plain;
    // Without the commit's messages (a frame taken over mid-way) every tracer gets a snapshot.
    const bool current =
        messages != nullptr && work_.frame > 0 && t.replica_commit == work_.frame - 1;
    if (!current) {
        auto& snapshot = snapshots[t.wants_bvh ? 1 : 0];
        if (!snapshot) snapshot = commit.snapshot(t.wants_bvh);
        messages = &*snapshot;
    }
    for (const std::string& m : *messages)
        t.session->send(m);
    t.replica_commit = work_.frame;
    t.from_snapshot = !current;
    t.assigned.clear();
    t.render_ms = 0.0;
    t.update_ms = 0.0;
    t.tile_rows = 0;
    t.stole_at.reset();
}

void TracerPool::split_rows(const std::vector<uint64_t>& ids) {
    // A new render size makes last frame's rows and unit costs meaningless: start even.
    const bool resized = last_unit_cost_.size() != units_.size();
    BalanceInput in{work_.height, {}, resized ? std::vector<double>{} : last_unit_cost_};
    for (uint64_t id : ids) {  // tracers that did not render the previous frame are new to it
        const Tracer& t = tracers_.at(id);
        const bool known = !resized && work_.frame > 0 && t.measured_frame == work_.frame - 1;
        in.last.push_back(known ? t.measured : TracerFrame{});
    }
    const std::vector<RowRange> ranges = balancer_->assign(in);
    for (std::size_t i = 0; i < ids.size(); ++i) {
        Tracer& t = tracers_.at(ids[i]);
        t.first_assignment = ranges[i];
        if (!ranges[i].empty()) assign(ids[i], t, ranges[i]);
    }
}

void TracerPool::assign(uint64_t id, Tracer& t, const RowRange& r) {
    wire::Assignment a{work_.frame,
                       work_.frame,
                       uint32_t(r.y0),
                       uint32_t(r.y1),
                       uint32_t(work_.width),
                       uint32_t(work_.height),
                       uint32_t(work_.spp),
                       work_.seed,
                       uint32_t(work_.max_depth),
                       work_.rr_scale,
                       work_.first_hits,
                       work_.light_sampling,
                       work_.extra_samples_zstd};
    t.session->send(wire::encode_assignment(a));
    t.assigned.push_back(r);
    t.news_at = now_();
    spdlog::debug("frame {}: rows [{}, {}) to tracer {} \"{}\"", work_.frame, r.y0, r.y1, id,
                  t.name);
}

void TracerPool::on_tile(uint64_t id, const std::string& bytes) {
    auto tile = wire::decode_tile(bytes);
    std::lock_guard lock(mutex_);
    const auto it = tracers_.find(id);
    if (it == tracers_.end()) return;
    if (!tile)
        return it->second.session->reject(net::ProtocolError::malformed, tile.error().message);
    if (!assembler_ || tile->frame != work_.frame) return;  // a tile of a frame already closed
    const RowRange range{int(tile->y0), int(tile->y1)};
    const std::size_t floats =
        std::size_t(std::max(0, range.rows())) * std::size_t(work_.width) * 3;
    auto rgb = decompress_floats(tile->rgb_zstd, floats);
    if (range.y1 > work_.height || !rgb)
        return it->second.session->reject(net::ProtocolError::malformed,
                                          "tile rows or pixels do not fit the frame");
    Result<std::vector<FirstHit>> hits = std::vector<FirstHit>{};
    if (work_.first_hits) hits = decode_first_hits(tile->first_hits_zstd, floats / 3);
    if (!hits)
        return it->second.session->reject(
            net::ProtocolError::malformed,
            "tile without the first hits its assignment asked for: " + hits.error().message);
    assembler_->add(range, rgb->data(), work_.first_hits ? hits->data() : nullptr);
    Tracer& t = it->second;
    t.render_ms += tile->render_ms;
    t.update_ms += tile->update_ms;
    t.tile_rows += range.rows();
    t.news_at = now_();
    if (t.stole_at) {
        spdlog::debug("frame {}: steal overhead of tracer \"{}\": {:.2f} ms", work_.frame, t.name,
                      ms_between(*t.stole_at, t.news_at) - tile->render_ms);
        t.stole_at.reset();
    }
    const std::size_t unit0 = std::size_t(range.y0 / kRowsPerWorkUnit);
    for (std::size_t k = 0; k < tile->unit_rays.size() && unit0 + k < units_.size(); ++k)
        units_[unit0 + k].rays = double(tile->unit_rays[k]);
    for (std::size_t k = 0; k < tile->unit_cost_us.size() && unit0 + k < units_.size(); ++k)
        units_[unit0 + k] = UnitReport{units_[unit0 + k].rays, double(tile->unit_cost_us[k]), id};
    tile_bytes_ += bytes.size();
    if (balancer_->steals_mid_frame() && !assembler_->complete()) steal_for(id);
    cv_.notify_all();
}

std::vector<RowRange> TracerPool::missing_of(const Tracer& t) const {
    std::vector<RowRange> out;
    if (!assembler_) return out;  // between frames nothing is owed
    for (const RowRange& r : t.assigned)
        for (const RowRange& m : assembler_->missing(r))
            out.push_back(m);
    return out;
}

bool TracerPool::idle(const Tracer& t) const { return missing_of(t).empty(); }

void TracerPool::steal_for(uint64_t id) {
    const Clock::time_point now = now_();
    std::vector<TracerProgress> progress;
    for (const auto& [other, t] : tracers_)
        progress.push_back({other, missing_of(t), t.replica_commit == work_.frame,
                            t.tile_rows > 0 ? t.render_ms / t.tile_rows : 0.0,
                            std::max(0.0, ms_between(t.news_at, now))});
    const auto steal = choose_steal(id, progress, kStealLatencyMs);
    if (!steal) return;
    Tracer& thief = tracers_.at(id);
    assign(id, thief, steal->rows);
    thief.stole_at = now;
    // The victim stops before the stolen rows instead of rendering them too.
    Tracer& v = tracers_.at(steal->victim);
    for (RowRange& r : v.assigned)
        if (r.y0 < steal->rows.y0 && steal->rows.y0 < r.y1) r.y1 = steal->rows.y0;
    v.session->send(wire::encode_truncation({work_.frame, work_.frame, uint32_t(steal->rows.y0)}));
}

void TracerPool::on_closed(uint64_t id) {
    std::lock_guard lock(mutex_);
    const auto it = tracers_.find(id);
    if (it == tracers_.end()) return;
    spdlog::warn("tracer \"{}\" left", it->second.name);
    const std::vector<RowRange> lost = missing_of(it->second);
    tracers_.erase(it);
    reissue(lost, false);  // its rows that never arrived go to the others now
    cv_.notify_all();
}

void TracerPool::reissue(const std::vector<RowRange>& ranges, bool idle_only) {
    if (ranges.empty()) return;
    std::vector<uint64_t> targets;
    for (const auto& [id, t] : tracers_)
        if (t.replica_commit == work_.frame && (!idle_only || idle(t))) targets.push_back(id);
    if (targets.empty() && idle_only) return reissue(ranges, false);
    if (targets.empty()) return;
    for (const RowRange& range : ranges) {
        const auto parts = split_range(range, int(targets.size()));
        for (std::size_t i = 0; i < parts.size(); ++i)
            if (!parts[i].empty()) assign(targets[i], tracers_.at(targets[i]), parts[i]);
    }
}

TracerPool::Wait TracerPool::wait_for_frame(const std::atomic<bool>& stop) {
    std::unique_lock lock(mutex_);
    auto deadline = Clock::now() + deadline_;
    while (!assembler_->complete()) {
        if (stop) return Wait::stopped;
        const bool any_synced = std::any_of(tracers_.begin(), tracers_.end(), [&](const auto& kv) {
            return kv.second.replica_commit == work_.frame;
        });
        if (!any_synced && !tracers_.empty()) {
            if (!adopt_frame()) {
                spdlog::warn("frame {}: every tracer of this frame left; continuing with the next",
                             work_.frame);
                return Wait::abandoned;
            }
            deadline = Clock::now() + deadline_;
        }
        cv_.wait_until(lock, std::min(deadline, Clock::now() + std::chrono::milliseconds(100)));
        if (Clock::now() >= deadline && !assembler_->complete()) {
            drop_silent();
            const auto missing = assembler_->missing({0, work_.height});
            spdlog::warn("frame {}: {} row range(s) missed the {} ms deadline; re-issuing",
                         work_.frame, missing.size(), deadline_.count());
            reissue(missing, true);
            deadline = Clock::now() + deadline_;
        }
    }
    return Wait::complete;
}

// Every tracer of the frame left and others are here: they get a snapshot of the frame and
// all its missing rows, if the snapshot still describes it. False: the frame is lost.
bool TracerPool::adopt_frame() {
    if (!commit_.snapshot_during_frame || !commit_.snapshot) return false;
    std::optional<std::vector<std::string>> snapshots[2];
    for (auto& [id, t] : tracers_)
        sync(t, commit_, snapshots);
    const auto missing = assembler_->missing({0, work_.height});
    spdlog::warn(
        "frame {}: every tracer of this frame left; {} tracer(s) take its {} missing "
        "row range(s)",
        work_.frame, tracers_.size(), missing.size());
    reissue(missing, false);
    return true;
}

// A tracer that owes rows and has sent nothing for a whole deadline (no tile since its last
// assignment) is taken to be gone, whatever its socket says: a half-open connection or a
// stalled link looks alive forever and would cost every later frame a deadline. It is closed
// (it reconnects if it is alive) and its rows go to the others.
void TracerPool::drop_silent() {
    const Clock::time_point now = now_();
    for (auto it = tracers_.begin(); it != tracers_.end();) {
        Tracer& t = it->second;
        if (idle(t) || ms_between(t.news_at, now) < double(deadline_.count())) {
            ++it;
            continue;
        }
        spdlog::warn("frame {}: tracer \"{}\" sent nothing for {} ms; disconnecting it",
                     work_.frame, t.name, deadline_.count());
        t.session->close("silent past the deadline");
        it = tracers_.erase(it);  // its rows are among the missing ones re-issued next
    }
}

FrameOutcome TracerPool::finish() {
    std::lock_guard lock(mutex_);
    FrameOutcome out{
        assembler_->take_image(), assembler_->take_first_hits(), 0.0, tile_bytes_, {}, units_};
    assembler_.reset();  // the frame is closed: its late tiles find none open
    last_unit_cost_ = unit_cost_map(units_);
    std::vector<double> busy;
    for (auto& [id, t] : tracers_) {
        if (t.replica_commit != work_.frame || t.render_ms <= 0.0) continue;
        busy.push_back(t.render_ms);
        out.tracers.push_back({t.name, t.first_assignment, t.render_ms,
                               delivered_rows(units_, id, work_.height), t.update_ms,
                               t.from_snapshot});
        t.measured_frame = work_.frame;
        t.measured = tracer_feedback(t.first_assignment, t.render_ms,
                                     delivered_cost(units_, last_unit_cost_, id));
    }
    out.idle_pct = idle_percent(busy);
    return out;
}

std::vector<std::shared_ptr<net::Session>> TracerPool::stop_accepting() {
    std::lock_guard lock(mutex_);
    accepting_ = false;
    std::vector<std::shared_ptr<net::Session>> sessions;
    for (auto& [id, t] : tracers_)
        sessions.push_back(t.session);
    tracers_.clear();
    return sessions;
}

}  // namespace pathfarm::coord
