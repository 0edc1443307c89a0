// FloatImage: linear float RGB radiance, row 0 at the top (DESIGN.md, "Conventions").
#pragma once

#include <cstddef>
#include <vector>

#include "common/math/types.h"

namespace pathfarm {

struct FloatImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // width * height * 3

    FloatImage() = default;
    FloatImage(int w, int h) : width(w), height(h), rgb(std::size_t(w) * h * 3, 0.0f) {}

    float* row(int y) { return rgb.data() + std::size_t(y) * width * 3; }
    const float* row(int y) const { return rgb.data() + std::size_t(y) * width * 3; }
    Rgb pixel(int x, int y) const {
        const float* p = row(y) + 3 * x;
        return {p[0], p[1], p[2]};
    }
    void set_pixel(int x, int y, const Rgb& c) {
        float* p = row(y) + 3 * x;
        p[0] = c.x;
        p[1] = c.y;
        p[2] = c.z;
    }
};

// Number of NaN or Inf values in the image.
std::size_t count_nonfinite(const FloatImage& image);

}  // namespace pathfarm
