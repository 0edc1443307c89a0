// Row bookkeeping for frame assembly.
#include "coordinator/frame/frame_assembler.h"

#include <algorithm>
#include <cstring>

namespace pathfarm::coord {

int FrameAssembler::add(const RowRange& range, const float* rgb, const FirstHit* hits) {
    int added = 0;
    const std::size_t row_floats = std::size_t(image_.width) * 3;
    for (int y = std::max(0, range.y0); y < std::min(image_.height, range.y1); ++y) {
        if (done_[std::size_t(y)]) continue;
        std::memcpy(image_.row(y), rgb + std::size_t(y - range.y0) * row_floats,
                    row_floats * sizeof(float));
        if (hits && !hits_.empty())
            std::copy_n(hits + std::size_t(y - range.y0) * image_.width, image_.width,
                        hits_.begin() + std::ptrdiff_t(y) * image_.width);
        done_[std::size_t(y)] = true;
        ++added;
    }
    missing_rows_ -= added;
    return added;
}

std::vector<RowRange> FrameAssembler::missing(const RowRange& within) const {
    std::vector<RowRange> out;
    for (int y = std::max(0, within.y0); y < std::min(image_.height, within.y1); ++y) {
        if (done_[std::size_t(y)]) continue;
        if (!out.empty() && out.back().y1 == y)
            ++out.back().y1;
        else
            out.push_back({y, y + 1});
    }
    return out;
}

}  // namespace pathfarm::coord
