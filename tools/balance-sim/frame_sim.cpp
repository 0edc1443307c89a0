// One simulated frame (frame_sim.h).
#include "tools/balance-sim/frame_sim.h"

#include <algorithm>

#include "common/base/check.h"
#include "coordinator/balance/steal.h"

namespace pathfarm::sim {

using coord::RowRange;

FrameSim::FrameSim(const std::vector<double>& cost, std::vector<double> speeds, double latency_ms,
                   int units_per_tile, bool steals)
    : cost_(cost),
      latency_ms_(latency_ms),
      units_per_tile_(std::max(1, units_per_tile)),
      steals_(steals),
      height_(int(cost.size()) * kRowsPerWorkUnit),
      tracers_(speeds.size()),
      units_(cost.size()),
      delivered_(cost.size(), false) {
    for (std::size_t i = 0; i < speeds.size(); ++i)
        tracers_[i].speed = speeds[i];
}

void FrameSim::run(const std::vector<RowRange>& ranges) {
    for (std::size_t i = 0; i < tracers_.size() && i < ranges.size(); ++i) {
        if (ranges[i].empty()) continue;
        tracers_[i].assigned.push_back(ranges[i]);
        tracers_[i].news_at = 0.0;
        push({latency_ms_, Kind::assignment, i, ranges[i], 0.0});
    }
    while (!events_.empty() && delivered_count_ < cost_.size()) {
        const Event e = events_.top();
        events_.pop();
        Tracer& t = tracers_[e.tracer];
        switch (e.kind) {
            case Kind::assignment:
                t.received.push_back(e.rows);
                for (int u = e.rows.y0 / kRowsPerWorkUnit; u * kRowsPerWorkUnit < e.rows.y1; ++u)
                    t.queue.push_back(u);
                if (!t.busy) start_next(e.tracer, e.t);
                break;
            case Kind::truncation:
                truncate(t, e.rows.y0);
                break;
            case Kind::unit_done:
                on_unit_done(e.tracer, e.rows.y0 / kRowsPerWorkUnit, e.t);
                break;
            case Kind::tile:
                on_tile(e);
                break;
        }
    }
    PF_CHECK_EQ(delivered_count_, cost_.size());  // every unit has an owner until it arrives
}

// The rows from `row` on of the assignment that contains it went to another tracer: its queued
// units there are dropped (one being rendered is finished, as the farm's tracers do).
void FrameSim::truncate(Tracer& t, int row) {
    for (RowRange& r : t.received) {
        if (!(r.y0 < row && row < r.y1)) continue;
        t.queue.erase(std::remove_if(t.queue.begin(), t.queue.end(),
                                     [&](int u) {
                                         const int y = u * kRowsPerWorkUnit;
                                         return y >= row && y < r.y1;
                                     }),
                      t.queue.end());
        r.y1 = row;
    }
}

void FrameSim::start_next(std::size_t i, double t) {
    Tracer& tr = tracers_[i];
    tr.busy = !tr.queue.empty();
    if (!tr.busy) return;
    const int u = tr.queue.front();
    tr.queue.pop_front();
    if (tr.tile_first < 0) {
        tr.tile_first = u;
        tr.tile_start = t;
    }
    const double ms = cost_[std::size_t(u)] / tr.speed;
    units_[std::size_t(u)].us = 1000.0 * ms;  // what this tracer will report for the unit
    push({t + ms, Kind::unit_done, i, RowRange{u * kRowsPerWorkUnit, u * kRowsPerWorkUnit}, 0.0});
}

// A tile goes out every units_per_tile units, at the end of an assignment, and when the next
// queued unit does not follow (a truncation or a new assignment elsewhere in the frame).
void FrameSim::on_unit_done(std::size_t i, int unit, double t) {
    Tracer& tr = tracers_[i];
    tr.tile_last = unit;
    const bool full = unit - tr.tile_first + 1 >= units_per_tile_;
    if (full || tr.queue.empty() || tr.queue.front() != unit + 1) send_tile(i, t);
    start_next(i, t);
}

void FrameSim::send_tile(std::size_t i, double t) {
    Tracer& tr = tracers_[i];
    const RowRange rows{tr.tile_first * kRowsPerWorkUnit,
                        std::min(height_, (tr.tile_last + 1) * kRowsPerWorkUnit)};
    tr.render_ms += t - tr.tile_start;
    push({t + latency_ms_, Kind::tile, i, rows, t - tr.tile_start});
    tr.tile_first = tr.tile_last = -1;
}

void FrameSim::on_tile(const Event& e) {
    Tracer& tr = tracers_[e.tracer];
    tr.heard_ms += e.render_ms;
    tr.heard_rows += e.rows.rows();
    tr.news_at = e.t;
    for (int u = e.rows.y0 / kRowsPerWorkUnit; u * kRowsPerWorkUnit < e.rows.y1; ++u) {
        coord::UnitReport& r = units_[std::size_t(u)];
        r.rays = cost_[std::size_t(u)];  // a speed-independent cost, as the farm's rays are
        r.owner = e.tracer + 1;
        if (delivered_[std::size_t(u)]) continue;
        delivered_[std::size_t(u)] = true;
        ++delivered_count_;
        tr.useful_ms += cost_[std::size_t(u)] / tr.speed;
    }
    if (delivered_count_ == cost_.size()) {
        frame_ms_ = e.t;
        return;
    }
    if (steals_) steal_for(e.tracer, e.t);
}

std::vector<RowRange> FrameSim::missing_of(const Tracer& t) const {
    std::vector<RowRange> out;
    for (const RowRange& r : t.assigned)
        for (int u = r.y0 / kRowsPerWorkUnit; u * kRowsPerWorkUnit < r.y1; ++u) {
            if (delivered_[std::size_t(u)]) continue;
            const RowRange unit{u * kRowsPerWorkUnit, std::min(r.y1, (u + 1) * kRowsPerWorkUnit)};
            if (!out.empty() && out.back().y1 == unit.y0)
                out.back().y1 = unit.y1;
            else
                out.push_back(unit);
        }
    return out;
}

void FrameSim::steal_for(std::size_t thief, double t) {
    std::vector<coord::TracerProgress> progress;
    for (std::size_t k = 0; k < tracers_.size(); ++k) {
        const Tracer& tr = tracers_[k];
        progress.push_back({k + 1, missing_of(tr), true,
                            tr.heard_rows > 0 ? tr.heard_ms / tr.heard_rows : 0.0,
                            std::max(0.0, t - tr.news_at)});
    }
    // The thief's rows start arriving after its assignment went out and its tile came back.
    const auto steal = coord::choose_steal(thief + 1, progress, 2.0 * latency_ms_);
    if (!steal) return;
    const std::size_t victim = steal->victim - 1;
    tracers_[thief].assigned.push_back(steal->rows);
    tracers_[thief].news_at = t;
    for (RowRange& r : tracers_[victim].assigned)
        if (r.y0 < steal->rows.y0 && steal->rows.y0 < r.y1) r.y1 = steal->rows.y0;
    push({t + latency_ms_, Kind::assignment, thief, steal->rows, 0.0});
    push({t + latency_ms_, Kind::truncation, victim, steal->rows, 0.0});
}

double FrameSim::farm_idle_pct() const {
    std::vector<double> busy;
    for (const Tracer& t : tracers_)
        if (t.render_ms > 0.0) busy.push_back(t.render_ms);
    return coord::idle_percent(busy);
}

double FrameSim::strict_idle_pct() const {
    if (!(frame_ms_ > 0.0) || tracers_.empty()) return 0.0;
    double idle = 0.0;
    for (const Tracer& t : tracers_)
        idle += frame_ms_ - t.useful_ms;
    return 100.0 * idle / (double(tracers_.size()) * frame_ms_);
}

std::vector<coord::TracerFrame> FrameSim::feedback(const std::vector<RowRange>& first,
                                                   std::vector<double>& unit_cost) const {
    unit_cost = coord::unit_cost_map(units_);
    std::vector<coord::TracerFrame> out;
    for (std::size_t i = 0; i < tracers_.size(); ++i) {
        const double cost = coord::delivered_cost(units_, unit_cost, i + 1);
        out.push_back(tracers_[i].render_ms > 0.0
                          ? coord::tracer_feedback(first[i], tracers_[i].render_ms, cost)
                          : coord::TracerFrame{});
    }
    return out;
}

}  // namespace pathfarm::sim
