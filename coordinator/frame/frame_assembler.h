// Assembles one frame from tiles: which rows arrived, the image, and what is still missing.
// Rendering is deterministic, so when a re-issued range arrives twice the first copy wins.
#pragma once

#include <vector>

#include "common/film/film.h"
#include "coordinator/balance/row_range.h"

namespace pathfarm::coord {

class FrameAssembler {
public:
    FrameAssembler(int width, int height)
        : image_(width, height), done_(std::size_t(height), false) {}

    // Copies rows [range.y0, range.y1) from rgb (rows * width * 3 floats). Returns the number
    // of rows that were new.
    int add(const RowRange& range, const float* rgb);
    bool complete() const { return missing_rows_ == 0; }
    // Maximal runs of rows not yet received within `within`.
    std::vector<RowRange> missing(const RowRange& within) const;
    const FloatImage& image() const { return image_; }

private:
    FloatImage image_;
    std::vector<bool> done_;
    int missing_rows_ = image_.height;
};

}  // namespace pathfarm::coord
