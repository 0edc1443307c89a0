// The mid-frame steal rule (steal.h).
#include "coordinator/balance/steal.h"

#include <algorithm>
#include <cmath>

#include "common/base/work_unit.h"
#include "coordinator/balance/balancer.h"

namespace pathfarm::coord {
namespace {

// A possible victim's work as the coordinator can estimate it.
struct Backlog {
    uint64_t id = 0;
    double pace = 0.0;          // ms per row
    double remaining_ms = 0.0;  // what it still has to render
    RowRange stealable;         // the part of its last gap it has not reached
};

Backlog backlog_of(const TracerProgress& t, double fallback_pace) {
    Backlog b{t.id, t.ms_per_row, 0.0, t.missing.back()};
    int missing = 0;
    for (const RowRange& m : t.missing)
        missing += m.rows();
    // Rows rendered since the last news, taken from the front. Without a tile this frame its
    // progress is unknown: it is somewhere in its first unit, which is never taken, and as no
    // tile came for that long, it is at least this slow.
    double ahead = 0.0;
    if (b.pace > 0.0) {
        ahead = t.ms_since_news / b.pace;
    } else {
        ahead = t.ms_since_news > 0.0 ? 1.0 : 0.0;
        b.pace = std::max(fallback_pace, t.ms_since_news / kRowsPerTile);
    }
    const double remaining_rows = std::max(0.0, double(missing) - ahead);
    b.remaining_ms = remaining_rows * (b.pace > 0.0 ? b.pace : 1.0);
    // The last gap's rows not reached yet begin this far from its end, on a unit boundary.
    const int left = int(std::floor(std::min(remaining_rows, double(b.stealable.rows()))));
    const int y0 = std::max(b.stealable.y0, b.stealable.y1 - left);
    b.stealable.y0 = std::min(b.stealable.y1, work_units(y0) * kRowsPerWorkUnit);
    return b;
}

}  // namespace

std::optional<Steal> choose_steal(uint64_t thief, const std::vector<TracerProgress>& tracers,
                                  double latency_ms) {
    double thief_pace = 0.0;
    for (const TracerProgress& t : tracers)
        if (t.id == thief) {
            if (!t.missing.empty()) return std::nullopt;  // still busy with its own rows
            thief_pace = t.ms_per_row;
        }
    std::optional<Backlog> victim;
    for (const TracerProgress& t : tracers) {
        if (t.id == thief || !t.can_take || t.missing.empty()) continue;
        const Backlog b = backlog_of(t, thief_pace);
        if (!victim || b.remaining_ms > victim->remaining_ms) victim = b;
    }
    if (!victim || victim->stealable.empty()) return std::nullopt;
    // Without any pace, rows stand for time and the latency is not comparable: ignore it.
    const double pace = victim->pace > 0.0 ? victim->pace : 1.0;
    const double thief_ms_per_row = thief_pace > 0.0 ? thief_pace : pace;
    const double latency = victim->pace > 0.0 ? latency_ms : 0.0;
    // The whole-unit tail that ends the frame soonest (the frame's last unit may be short).
    const int last_unit = (victim->stealable.y1 - 1) / kRowsPerWorkUnit;
    const int first_unit = victim->stealable.y0 / kRowsPerWorkUnit;
    const auto finish = [&](int y0) {
        const int rows = victim->stealable.y1 - y0;
        return std::max(victim->remaining_ms - rows * pace, latency + rows * thief_ms_per_row);
    };
    int best_y0 = victim->stealable.y1;
    double best = victim->remaining_ms;
    for (int u = last_unit; u >= first_unit; --u)
        if (const double f = finish(u * kRowsPerWorkUnit); f < best) {
            best = f;
            best_y0 = u * kRowsPerWorkUnit;
        }
    if (victim->remaining_ms - best < kRowsPerWorkUnit * pace) return std::nullopt;
    const RowRange rows{best_y0, victim->stealable.y1};
    return Steal{victim->id, rows};
}

}  // namespace pathfarm::coord
