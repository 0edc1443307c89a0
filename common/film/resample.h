// Resampling for display: frames rendered below the display resolution (workload scaling)
// are upscaled bilinearly before converging and encoding.
#pragma once

#include <algorithm>

#include "common/film/film.h"

namespace pathfarm {

// `image` at pixel coordinates (sx, sy), a pixel's centre at x + 0.5, bilinear, the border
// pixels extended. Inline: the per-pixel loops that call it (resizing, the denoiser's temporal
// anti-aliasing) are in other libraries.
inline Rgb sample_bilinear(const FloatImage& image, float sx, float sy) {
    const float fx = std::clamp(sx - 0.5f, 0.0f, float(image.width - 1));
    const float fy = std::clamp(sy - 0.5f, 0.0f, float(image.height - 1));
    const int x0 = int(fx), x1 = std::min(x0 + 1, image.width - 1);
    const int y0 = int(fy), y1 = std::min(y0 + 1, image.height - 1);
    const float tx = fx - float(x0), ty = fy - float(y0);
    const Rgb top = image.pixel(x0, y0) * (1.0f - tx) + image.pixel(x1, y0) * tx;
    const Rgb bottom = image.pixel(x0, y1) * (1.0f - tx) + image.pixel(x1, y1) * tx;
    return top * (1.0f - ty) + bottom * ty;
}

FloatImage resize_bilinear(const FloatImage& image, int width, int height);
// Rows [y0, y1) of that resize into `out`, already of the new size (a caller's threads each
// take some rows: coordinator/frame/parallel_image.h).
void resize_bilinear_rows(const FloatImage& image, FloatImage& out, int y0, int y1);

}  // namespace pathfarm
