// Rows of an image in parallel (TBB), one call per row: the converge passes' loop shape.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace pathfarm::coord {

template <typename F>
void parallel_rows(int height, F&& per_row) {
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
            per_row(y);
    });
}

}  // namespace pathfarm::coord
