// The mid-frame steal rule (steal.h).
#include "coordinator/balance/steal.h"

#include <algorithm>

namespace pathfarm::coord {

std::optional<Steal> choose_steal(uint64_t thief, const std::vector<TracerProgress>& tracers) {
    std::optional<RowRange> gap;
    uint64_t victim = 0;
    int most = 0;
    for (const TracerProgress& t : tracers) {
        if (t.id == thief) {
            if (!t.missing.empty()) return std::nullopt;  // still busy with its own rows
            continue;
        }
        if (!t.can_take || t.missing.empty()) continue;
        int missing = 0;
        for (const RowRange& m : t.missing)
            missing += m.rows();
        if (missing > most) {
            most = missing;
            gap = t.missing.back();
            victim = t.id;
        }
    }
    if (!gap || gap->rows() < 2 * kRowsPerWorkUnit) return std::nullopt;
    const int units = (gap->rows() / kRowsPerWorkUnit) / 2;
    const int y0 = std::max(gap->y0, gap->y1 - units * kRowsPerWorkUnit);
    return Steal{victim, RowRange{y0 - y0 % kRowsPerWorkUnit, gap->y1}};
}

}  // namespace pathfarm::coord
