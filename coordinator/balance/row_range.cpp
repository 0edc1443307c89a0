// Equal splits on work-unit boundaries.
#include "coordinator/balance/row_range.h"

#include <algorithm>

namespace pathfarm::coord {

std::vector<RowRange> split_range(const RowRange& range, int parts) {
    std::vector<RowRange> out;
    if (parts <= 0 || range.empty()) return out;
    const int units = (range.rows() + kRowsPerWorkUnit - 1) / kRowsPerWorkUnit;
    int unit = 0;
    for (int p = 0; p < parts; ++p) {
        const int take = units / parts + (p < units % parts ? 1 : 0);
        const int y0 = std::min(range.y1, range.y0 + unit * kRowsPerWorkUnit);
        unit += take;
        const int y1 = std::min(range.y1, range.y0 + unit * kRowsPerWorkUnit);
        out.push_back({y0, std::max(y0, y1)});
    }
    return out;
}

std::vector<RowRange> split_rows_equally(int height, int tracers) {
    return split_range({0, height}, tracers);
}

}  // namespace pathfarm::coord
