// Bilinear resizing (workload scaling's upscale for display) against its definition.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/film/resample.h"

namespace pathfarm {
namespace {

FloatImage random_image(int w, int h, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 3.0f);
    FloatImage img(w, h);
    for (float& v : img.rgb)
        v = u(rng);
    return img;
}

// Every pixel of a resize is sample_bilinear at its centre, bit for bit, for random sizes up
// and down (one-pixel images and strips included).
TEST(ResizeBilinear, EveryPixelIsTheBilinearSampleAtItsCentre) {
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> size(1, 90);
    for (int c = 0; c < 40; ++c) {
        const FloatImage in = random_image(size(rng), size(rng), rng);
        const int w = size(rng), h = size(rng);
        const FloatImage out = resize_bilinear(in, w, h);
        ASSERT_EQ(out.width, w);
        ASSERT_EQ(out.height, h);
        const float sx = float(in.width) / float(w), sy = float(in.height) / float(h);
        int wrong = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                wrong += out.pixel(x, y) != sample_bilinear(in, (x + 0.5f) * sx, (y + 0.5f) * sy);
        EXPECT_EQ(wrong, 0) << in.width << "x" << in.height << " to " << w << "x" << h;
    }
}

// What bilinear interpolation must keep: a constant stays constant, a ramp along x stays a
// ramp between the outermost centres, and the same size is the image itself.
TEST(ResizeBilinear, KeepsConstantsAndRamps) {
    FloatImage flat(7, 5);
    for (float& v : flat.rgb)
        v = 0.625f;
    for (const float v : resize_bilinear(flat, 23, 11).rgb)
        EXPECT_EQ(v, 0.625f);
    FloatImage ramp(8, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 8; ++x)
            ramp.set_pixel(x, y, Rgb(float(x)));
    const FloatImage up = resize_bilinear(ramp, 32, 4);  // centres at (x + 0.5) / 4 - 0.5
    for (int x = 2; x < 30; ++x)
        EXPECT_NEAR(up.pixel(x, 1).x, (x + 0.5f) / 4.0f - 0.5f, 1e-5f) << x;
    EXPECT_EQ(up.pixel(0, 0).x, 0.0f);  // the border extended
    EXPECT_EQ(up.pixel(31, 3).x, 7.0f);
    std::mt19937 rng(5);
    const FloatImage same = random_image(9, 4, rng);
    EXPECT_EQ(resize_bilinear(same, 9, 4).rgb, same.rgb);
}

}  // namespace
}  // namespace pathfarm
