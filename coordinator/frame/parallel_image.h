// The display stage's whole-image passes over rows in parallel (TBB, in whatever arena the
// caller runs: the display's): the upscale for display and the tonemap before encoding. The
// same bytes as the one-thread functions in common/film, which own the arithmetic; at 640x360
// the two were 2.3 and about 1.7 ms of the demo's display stage on one thread.
#pragma once

#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "common/film/film.h"
#include "common/film/resample.h"
#include "common/film/tonemap.h"

namespace pathfarm::coord {

// Rows in blocks of at least this many (each block also computes the resize's column taps).
inline constexpr int kImageRowsPerTask = 16;

inline FloatImage resize_bilinear_parallel(const FloatImage& image, int width, int height) {
    if (image.width == width && image.height == height) return image;
    FloatImage out(width, height);
    tbb::parallel_for(tbb::blocked_range<int>(0, height, kImageRowsPerTask),
                      [&](const tbb::blocked_range<int>& rows) {
                          resize_bilinear_rows(image, out, rows.begin(), rows.end());
                      });
    return out;
}

inline std::vector<uint8_t> tonemap_to_srgb8_parallel(const FloatImage& image,
                                                      float exposure = 1.0f) {
    std::vector<uint8_t> out(image.rgb.size());
    tbb::parallel_for(tbb::blocked_range<int>(0, image.height, kImageRowsPerTask),
                      [&](const tbb::blocked_range<int>& rows) {
                          tonemap_rows_to_srgb8(image, exposure, rows.begin(), rows.end(),
                                                out.data());
                      });
    return out;
}

}  // namespace pathfarm::coord
