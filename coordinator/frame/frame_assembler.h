// Assembles one frame from tiles: which rows arrived, the image, and what is still missing.
// Rendering is deterministic, so when a re-issued range arrives twice the first copy wins.
#pragma once

#include <utility>
#include <vector>

#include "common/film/film.h"
#include "common/film/first_hits.h"
#include "coordinator/balance/row_range.h"

namespace pathfarm::coord {

class FrameAssembler {
public:
    // `first_hits`: the frame's tiles carry first hits, assembled beside the image.
    FrameAssembler(int width, int height, bool first_hits = false)
        : image_(width, height),
          hits_(first_hits ? std::size_t(width) * height : 0),
          done_(std::size_t(height), false) {}

    // Copies rows [range.y0, range.y1) from rgb (rows * width * 3 floats) and, if the frame
    // has them, from hits (rows * width). Returns the number of rows that were new.
    int add(const RowRange& range, const float* rgb, const FirstHit* hits = nullptr);
    bool complete() const { return missing_rows_ == 0; }
    // Maximal runs of rows not yet received within `within`.
    std::vector<RowRange> missing(const RowRange& within) const;
    const FloatImage& image() const { return image_; }
    const std::vector<FirstHit>& first_hits() const { return hits_; }  // empty if not asked
    // The finished frame's buffers, moved out rather than copied (3.5 MB a frame at 320x180
    // with first hits); the assembler is spent afterwards.
    FloatImage take_image() { return std::move(image_); }
    std::vector<FirstHit> take_first_hits() { return std::move(hits_); }

private:
    FloatImage image_;
    std::vector<FirstHit> hits_;
    std::vector<bool> done_;
    int missing_rows_ = image_.height;
};

}  // namespace pathfarm::coord
