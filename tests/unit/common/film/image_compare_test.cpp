// SSIM against a direct evaluation of its definition (2-D windows, no separable passes) on
// random images, and the properties a similarity must have.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/film/image_compare.h"
#include "common/film/tonemap.h"

namespace pathfarm::image_compare_test {
namespace {

FloatImage random_image(int w, int h, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 2.0f);
    FloatImage img(w, h);
    for (float& v : img.rgb)
        v = u(rng) * u(rng);
    return img;
}

FloatImage noisy(const FloatImage& img, float amplitude, std::mt19937& rng) {
    std::normal_distribution<float> n(0.0f, amplitude);
    FloatImage out = img;
    for (float& v : out.rgb)
        v = std::max(0.0f, v + n(rng));
    return out;
}

// The definition, one pixel's 11x11 window at a time.
double direct_ssim(const FloatImage& a, const FloatImage& b) {
    const auto luma = [](const FloatImage& img) {
        const std::vector<uint8_t> s = tonemap_to_srgb8(img);
        std::vector<double> l(s.size() / 3);
        for (std::size_t i = 0; i < l.size(); ++i)
            l[i] = (0.299 * s[3 * i] + 0.587 * s[3 * i + 1] + 0.114 * s[3 * i + 2]) / 255.0;
        return l;
    };
    const std::vector<double> x = luma(a), y = luma(b);
    const int w = a.width, h = a.height;
    double total = 0.0;
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
            double sw = 0, mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
            for (int dy = -5; dy <= 5; ++dy)
                for (int dx = -5; dx <= 5; ++dx) {
                    const int qx = px + dx, qy = py + dy;
                    if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
                    // Renormalised per axis, as the separable passes do.
                    const double k = std::exp(-0.5 * (dx * dx + dy * dy) / 2.25);
                    const std::size_t i = std::size_t(qy) * w + qx;
                    sw += k;
                    mx += k * x[i];
                    my += k * y[i];
                    xx += k * x[i] * x[i];
                    yy += k * y[i] * y[i];
                    xy += k * x[i] * y[i];
                }
            mx /= sw, my /= sw, xx /= sw, yy /= sw, xy /= sw;
            const double c1 = 1e-4, c2 = 9e-4;
            total += (2 * mx * my + c1) * (2 * (xy - mx * my) + c2) /
                     ((mx * mx + my * my + c1) * (xx - mx * mx + yy - my * my + c2));
        }
    return total / (double(w) * h);
}

TEST(Ssim, MatchesItsDefinitionOnRandomImages) {
    std::mt19937 rng(5);
    for (int trial = 0; trial < 6; ++trial) {
        const int w = 8 + int(rng() % 30), h = 8 + int(rng() % 30);
        const FloatImage a = random_image(w, h, rng);
        const FloatImage b = noisy(a, 0.05f + 0.1f * trial, rng);
        EXPECT_NEAR(ssim(b, a), direct_ssim(b, a), 1e-9) << w << "x" << h;
    }
}

TEST(Ssim, IsOneForTheSameImageSymmetricAndFallsWithNoise) {
    std::mt19937 rng(9);
    const FloatImage a = random_image(40, 30, rng);
    EXPECT_NEAR(ssim(a, a), 1.0, 1e-12);
    double last = 1.0;
    for (float amplitude : {0.02f, 0.1f, 0.3f, 1.0f}) {
        const FloatImage b = noisy(a, amplitude, rng);
        const double s = ssim(b, a);
        EXPECT_NEAR(s, ssim(a, b), 1e-12);
        EXPECT_LT(s, last) << "noise " << amplitude;
        EXPECT_GT(s, -1.0);
        last = s;
    }
}

// A decoded frame is judged by its bytes: ssim8 is SSIM of the frames the bytes are.
TEST(Ssim8, MatchesSsimOfTheSameFrames) {
    std::mt19937 rng(21);
    for (int trial = 0; trial < 4; ++trial) {
        const int w = 8 + int(rng() % 30), h = 8 + int(rng() % 30);
        const FloatImage a = random_image(w, h, rng), b = noisy(a, 0.1f + 0.2f * trial, rng);
        const std::vector<uint8_t> a8 = tonemap_to_srgb8(a), b8 = tonemap_to_srgb8(b);
        EXPECT_NEAR(ssim8(b8, a8, w, h), direct_ssim(b, a), 1e-9) << w << "x" << h;
        EXPECT_NEAR(ssim8(a8, a8, w, h), 1.0, 1e-12);
    }
}

}  // namespace
}  // namespace pathfarm::image_compare_test
