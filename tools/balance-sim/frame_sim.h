// One simulated frame, event by event: the coordinator's messages (assignments, truncations)
// and the tracers' tiles take a latency each; tracers render their queued work units in order,
// timing each, and send a tile every few units as the farm's tracers do; the coordinator marks
// what arrived and, for a balancer that steals mid-frame, lets a tracer that ran out take rows
// with the very rule the farm ships (coordinator/balance/steal.h).
#pragma once

#include <cstdint>
#include <deque>
#include <queue>
#include <vector>

#include "coordinator/balance/row_range.h"
#include "coordinator/balance/unit_costs.h"

namespace pathfarm::sim {

class FrameSim {
public:
    // cost[u]: work unit u's cost in ms at speed 1; speeds: this frame's, per tracer.
    FrameSim(const std::vector<double>& cost, std::vector<double> speeds, double latency_ms,
             int units_per_tile, bool steals);

    // Runs the frame from the balancer's ranges (one per tracer, in order).
    void run(const std::vector<coord::RowRange>& ranges);

    double frame_ms() const { return frame_ms_; }
    // Idle as the farm reports it (coordinator/balance/unit_costs.h idle_percent over each
    // tracer's summed tile times) and as the simulator counts it: frame time not spent on
    // rows that tracer delivered first (re-rendered rows are idle).
    double farm_idle_pct() const;
    double strict_idle_pct() const;
    // What the farm would tell the balancer next frame: per tracer, and the cost map.
    std::vector<coord::TracerFrame> feedback(const std::vector<coord::RowRange>& first,
                                             std::vector<double>& unit_cost) const;

private:
    enum class Kind { assignment, truncation, unit_done, tile };
    struct Event {
        double t;
        Kind kind;
        std::size_t tracer;
        coord::RowRange rows;  // assignment / tile rows; truncation: rows.y0
        double render_ms;      // tile
        bool operator>(const Event& o) const { return t > o.t; }
    };
    struct Tracer {
        double speed = 1.0;
        std::deque<int> queue;  // units to render, in order
        bool busy = false;
        int tile_first = -1, tile_last = -1;  // units rendered since the last tile
        double tile_start = 0.0;
        double render_ms = 0.0;                 // summed tile times (the farm's busy)
        double useful_ms = 0.0;                 // time on units it delivered first
        std::vector<coord::RowRange> assigned;  // as the coordinator sees it
        double heard_ms = 0.0;                  // coordinator: tile times received
        int heard_rows = 0;                     // coordinator: rows of those tiles
        double news_at = 0.0;                   // coordinator: last tile or assignment
        std::vector<coord::RowRange> received;  // as the tracer sees it
    };
    void push(Event e) { events_.push(e); }
    void truncate(Tracer& t, int row);
    void start_next(std::size_t i, double t);
    void on_unit_done(std::size_t i, int unit, double t);
    void send_tile(std::size_t i, double t);
    void on_tile(const Event& e);
    void steal_for(std::size_t thief, double t);
    std::vector<coord::RowRange> missing_of(const Tracer& t) const;

    const std::vector<double>& cost_;
    double latency_ms_;
    int units_per_tile_;
    bool steals_;
    int height_;
    std::vector<Tracer> tracers_;
    std::vector<coord::UnitReport> units_;
    std::vector<bool> delivered_;
    std::size_t delivered_count_ = 0;
    double frame_ms_ = 0.0;
    std::priority_queue<Event, std::vector<Event>, std::greater<>> events_;
};

}  // namespace pathfarm::sim
