// Bilinear resize with pixel centres aligned (the centre of the image maps to itself).
#include "common/film/resample.h"

#include <algorithm>
#include <cmath>

namespace pathfarm {

FloatImage resize_bilinear(const FloatImage& image, int width, int height) {
    if (image.width == width && image.height == height) return image;
    FloatImage out(width, height);
    const float sx = float(image.width) / float(width), sy = float(image.height) / float(height);
    for (int y = 0; y < height; ++y) {
        const float fy = std::clamp((y + 0.5f) * sy - 0.5f, 0.0f, float(image.height - 1));
        const int y0 = int(fy), y1 = std::min(y0 + 1, image.height - 1);
        const float ty = fy - float(y0);
        for (int x = 0; x < width; ++x) {
            const float fx = std::clamp((x + 0.5f) * sx - 0.5f, 0.0f, float(image.width - 1));
            const int x0 = int(fx), x1 = std::min(x0 + 1, image.width - 1);
            const float tx = fx - float(x0);
            const Rgb top = image.pixel(x0, y0) * (1.0f - tx) + image.pixel(x1, y0) * tx;
            const Rgb bottom = image.pixel(x0, y1) * (1.0f - tx) + image.pixel(x1, y1) * tx;
            out.set_pixel(x, y, top * (1.0f - ty) + bottom * ty);
        }
    }
    return out;
}

}  // namespace pathfarm
