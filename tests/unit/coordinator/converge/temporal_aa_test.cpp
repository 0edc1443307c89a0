// The denoiser's temporal anti-aliasing (temporal_aa.h) on synthetic frames: it follows the
// motion it is given, cuts a history the new neighbourhood does not hold, averages noise over
// still frames without moving their mean, and leaves pixels without motion alone.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "coordinator/converge/temporal_aa.h"
#include "coordinator/converge/temporal_accumulator.h"

namespace pathfarm::coord::temporal_aa_test {
namespace {

constexpr int kW = 40, kH = 24;

std::vector<Vec2> identity_sources(int w, int h) {
    std::vector<Vec2> s(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            s[std::size_t(y) * w + x] = Vec2(x + 0.5f, y + 0.5f);
    return s;
}

// A ramp along x, brighter in green, shifted by `shift` pixels.
FloatImage ramp(float shift) {
    FloatImage image(kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const float v = 0.05f * (float(x) - shift) + 2.0f;
            image.set_pixel(x, y, Rgb(v, 2.0f * v, 0.5f * v + 0.01f * float(y)));
        }
    return image;
}

// A camera pan by a fraction of a pixel and by pixels: the history read where each pixel's
// surface was is what the new frame shows (bilinear is exact on a ramp), so the output is the
// new frame. Read where the pixel is instead (no motion), it would lag behind by the shift.
TEST(TemporalAntialias, FollowsTheMotionItIsGiven) {
    for (const float shift : {0.37f, 1.0f, 2.5f}) {
        TemporalAntialias taa(0.3f);
        FloatImage first = ramp(0.0f);
        taa.apply(first, identity_sources(kW, kH));
        FloatImage moved = ramp(shift);
        std::vector<Vec2> sources = identity_sources(kW, kH);
        for (Vec2& s : sources)
            s.x -= shift;  // the surface at x was at x - shift
        const FloatImage expected = moved;
        taa.apply(moved, sources);
        for (int y = 1; y + 1 < kH; ++y)
            for (int x = 4; x + 1 < kW; ++x)  // inside, clear of the clamped border
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(moved.pixel(x, y)[c], expected.pixel(x, y)[c], 1e-4f)
                        << "shift " << shift << " at " << x << "," << y;
    }
}

// A light switched on: the dark history lies outside the new neighbourhood's colours and is cut
// to them, so the lit region shows its new light at once, not 30 % of it.
TEST(TemporalAntialias, AHistoryTheNeighbourhoodDoesNotHoldIsCut) {
    TemporalAntialias taa(0.3f);
    FloatImage dark(kW, kH);
    taa.apply(dark, identity_sources(kW, kH));
    FloatImage lit(kW, kH);
    for (int y = 5; y < 15; ++y)
        for (int x = 10; x < 30; ++x)
            lit.set_pixel(x, y, Rgb(4.0f, 3.0f, 1.0f));
    taa.apply(lit, identity_sources(kW, kH));
    for (int y = 6; y < 14; ++y)
        for (int x = 11; x < 29; ++x)
            ASSERT_EQ(lit.pixel(x, y), Rgb(4.0f, 3.0f, 1.0f)) << x << "," << y;
}

// Noisy frames of a still grey wall: the output's error falls well below one frame's, and its
// mean stays the wall's (the clamp only ever pulls towards the new frame).
TEST(TemporalAntialias, StillFramesAverageTheirNoiseWithoutMovingTheMean) {
    TemporalAntialias taa(0.3f);
    std::mt19937 rng(11);
    std::normal_distribution<float> noise(0.0f, 0.1f);
    const std::vector<Vec2> sources = identity_sources(kW, kH);
    double raw_sq = 0.0, out_sq = 0.0, out_sum = 0.0;
    std::size_t count = 0;
    for (int frame = 0; frame < 40; ++frame) {
        FloatImage image(kW, kH);
        for (float& v : image.rgb)
            v = 0.5f + noise(rng);
        if (frame >= 20)
            for (const float v : image.rgb)
                raw_sq += double(v - 0.5f) * double(v - 0.5f);
        taa.apply(image, sources);
        if (frame < 20) continue;
        for (const float v : image.rgb) {
            out_sq += double(v - 0.5f) * double(v - 0.5f);
            out_sum += v;
            ++count;
        }
    }
    EXPECT_LT(std::sqrt(out_sq / raw_sq), 0.6);
    EXPECT_NEAR(out_sum / double(count), 0.5, 0.005);
}

// Pixels without motion (off screen, on or beside a moving object) keep the new output exactly,
// whatever the history held; so do the first frame and a new size.
TEST(TemporalAntialias, PixelsWithoutMotionAndNewSizesAreLeftAlone) {
    TemporalAntialias taa(0.3f);
    FloatImage bright(kW, kH);
    for (float& v : bright.rgb)
        v = 9.0f;
    FloatImage first = bright;
    taa.apply(first, identity_sources(kW, kH));
    EXPECT_EQ(first.rgb, bright.rgb);
    FloatImage dim(kW, kH);
    for (float& v : dim.rgb)
        v = 9.0f - float(&v - dim.rgb.data()) * 1e-4f;  // every pixel its own value
    const FloatImage expected = dim;
    std::vector<Vec2> none(std::size_t(kW) * kH, Vec2(kNoSource));
    taa.apply(dim, none);
    EXPECT_EQ(dim.rgb, expected.rgb);
    FloatImage larger(kW + 2, kH);
    const FloatImage larger_before = larger;
    taa.apply(larger, identity_sources(kW + 2, kH));
    EXPECT_EQ(larger.rgb, larger_before.rgb);
}

}  // namespace
}  // namespace pathfarm::coord::temporal_aa_test
