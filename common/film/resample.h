// Resampling for display: frames rendered below the display resolution (workload scaling)
// are upscaled bilinearly before converging and encoding.
#pragma once

#include <algorithm>

#include "common/film/film.h"

namespace pathfarm {

// Where a coordinate samples along one axis of `size` pixels (a pixel's centre at x + 0.5, the
// border pixels extended): its two pixels and the weight of the second.
struct BilinearTap {
    int a, b;
    float t;
};
inline BilinearTap bilinear_tap(float s, int size) {
    const float f = std::clamp(s - 0.5f, 0.0f, float(size - 1));
    const int a = int(f);
    return {a, std::min(a + 1, size - 1), f - float(a)};
}

// The image between the four pixels of a column tap `c` and a row tap `r`.
inline Rgb blend_taps(const FloatImage& image, const BilinearTap& c, const BilinearTap& r) {
    const Rgb top = image.pixel(c.a, r.a) * (1.0f - c.t) + image.pixel(c.b, r.a) * c.t;
    const Rgb bottom = image.pixel(c.a, r.b) * (1.0f - c.t) + image.pixel(c.b, r.b) * c.t;
    return top * (1.0f - r.t) + bottom * r.t;
}

// `image` at pixel coordinates (sx, sy), bilinear. Inline: the per-pixel loops that call it
// (the denoiser's temporal anti-aliasing) are in other libraries.
inline Rgb sample_bilinear(const FloatImage& image, float sx, float sy) {
    return blend_taps(image, bilinear_tap(sx, image.width), bilinear_tap(sy, image.height));
}

FloatImage resize_bilinear(const FloatImage& image, int width, int height);
// Rows [y0, y1) of that resize into `out`, already of the new size (a caller's threads each
// take some rows: coordinator/frame/parallel_image.h).
void resize_bilinear_rows(const FloatImage& image, FloatImage& out, int y0, int y1);

}  // namespace pathfarm
