// Row ranges and work units (DESIGN.md, "The frame" step 4). Pure: no I/O, no clock.
#pragma once

#include <vector>

#include "common/base/work_unit.h"

namespace pathfarm::coord {

struct RowRange {
    int y0 = 0;
    int y1 = 0;  // one past the last row
    int rows() const { return y1 - y0; }
    bool empty() const { return y1 <= y0; }
    bool operator==(const RowRange&) const = default;
};

// Contiguous ranges covering [0, height) exactly once, cut on 4-row work-unit boundaries,
// one per tracer, as equal as whole units allow (the last unit may be shorter than 4 rows).
std::vector<RowRange> split_rows_equally(int height, int tracers);
// Splits one range among `parts` in the same way (for re-issuing missing rows).
std::vector<RowRange> split_range(const RowRange& range, int parts);

}  // namespace pathfarm::coord
