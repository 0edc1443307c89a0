// The history clamp's neighbourhood statistics against nine taps per pixel in double, on images
// of random sizes (one-pixel rows and columns included) and values over many magnitudes.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "coordinator/converge/neighbourhood.h"

namespace pathfarm::coord {
namespace {

TEST(NeighbourhoodStats, MatchNineTapsOnRandomImages) {
    std::mt19937 rng(20261203);
    std::uniform_int_distribution<int> size(1, 40);
    std::uniform_real_distribution<float> exponent(-4.0f, 4.0f), unit(0.0f, 1.0f);
    NeighbourhoodStats stats;  // reused across sizes, as the accumulator does
    for (int trial = 0; trial < 60; ++trial) {
        const int w = trial < 4 ? 1 + trial % 2 : size(rng),
                  h = trial < 4 ? 1 + trial / 2 : size(rng);
        FloatImage image(w, h);
        for (float& v : image.rgb)
            v = unit(rng) * std::pow(10.0f, exponent(rng));
        stats.compute(image);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) {
                    double sum = 0.0, sum2 = 0.0, largest = 0.0;
                    int n = 0;
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            const int sx = x + dx, sy = y + dy;
                            if (sx < 0 || sy < 0 || sx >= w || sy >= h) continue;
                            const double v = image.rgb[3 * (std::size_t(sy) * w + sx) + c];
                            sum += v;
                            sum2 += v * v;
                            largest = std::max(largest, v);
                            ++n;
                        }
                    const double mean = sum / n;
                    const double sigma = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
                    const std::size_t i = std::size_t(y) * w + x;
                    ASSERT_NEAR(stats.mean(i)[c], mean, 1e-5 * largest)
                        << w << "x" << h << " pixel " << x << "," << y;
                    // The float variance cancels: its error is relative to the largest square.
                    ASSERT_NEAR(stats.sigma(i)[c], sigma, 3e-3 * largest + 1e-30)
                        << w << "x" << h << " pixel " << x << "," << y;
                }
    }
}

}  // namespace
}  // namespace pathfarm::coord
