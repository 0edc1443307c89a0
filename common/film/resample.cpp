// Bilinear resize with pixel centres aligned (the centre of the image maps to itself).
#include "common/film/resample.h"

namespace pathfarm {

FloatImage resize_bilinear(const FloatImage& image, int width, int height) {
    if (image.width == width && image.height == height) return image;
    FloatImage out(width, height);
    const float sx = float(image.width) / float(width), sy = float(image.height) / float(height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            out.set_pixel(x, y, sample_bilinear(image, (x + 0.5f) * sx, (y + 0.5f) * sy));
    return out;
}

}  // namespace pathfarm
