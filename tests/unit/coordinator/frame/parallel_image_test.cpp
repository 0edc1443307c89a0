// The display stage's parallel upscale and tonemap (coordinator/frame/parallel_image.h) give
// the one-thread functions' bytes, whatever the arena's threads and however the rows split.
#include <random>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "coordinator/frame/parallel_image.h"

namespace pathfarm::coord {
namespace {

FloatImage random_image(int w, int h, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-0.2f, 4.0f);
    FloatImage img(w, h);
    for (float& v : img.rgb)
        v = u(rng) * u(rng);
    return img;
}

TEST(ParallelImage, UpscaleAndTonemapEqualTheOneThreadFunctions) {
    std::mt19937 rng(23);
    std::uniform_int_distribution<int> size(1, 120);
    for (const int threads : {1, 2, 4}) {
        tbb::task_arena arena(threads);
        for (int c = 0; c < 12; ++c) {
            const FloatImage in = random_image(size(rng), size(rng), rng);
            const int w = size(rng), h = size(rng);
            arena.execute([&] {
                EXPECT_EQ(resize_bilinear_parallel(in, w, h).rgb, resize_bilinear(in, w, h).rgb)
                    << threads << " threads, " << in.width << "x" << in.height << " to " << w << "x"
                    << h;
                EXPECT_EQ(tonemap_to_srgb8_parallel(in, 0.7f), tonemap_to_srgb8(in, 0.7f))
                    << threads << " threads, " << in.width << "x" << in.height;
            });
        }
    }
}

// The row functions take any range: clipped to the image, empty where it is empty, and rows
// outside it untouched.
TEST(ParallelImage, RowRangesAreClippedToTheImage) {
    std::mt19937 rng(29);
    const FloatImage in = random_image(13, 9, rng);
    const std::vector<uint8_t> whole = tonemap_to_srgb8(in);
    std::vector<uint8_t> parts(whole.size(), 7);
    tonemap_rows_to_srgb8(in, 1.0f, -5, 4, parts.data());
    tonemap_rows_to_srgb8(in, 1.0f, 4, 4, parts.data());
    EXPECT_EQ(parts[std::size_t(4) * 13 * 3], 7) << "an empty range writes nothing";
    tonemap_rows_to_srgb8(in, 1.0f, 4, 50, parts.data());
    EXPECT_EQ(parts, whole);
    FloatImage out(20, 11), expected = resize_bilinear(in, 20, 11);
    resize_bilinear_rows(in, out, 6, 100);
    for (int y = 0; y < 11; ++y)
        for (int x = 0; x < 20; ++x)
            EXPECT_EQ(out.pixel(x, y), y < 6 ? Rgb(0.0f) : expected.pixel(x, y)) << x << "," << y;
}

}  // namespace
}  // namespace pathfarm::coord
