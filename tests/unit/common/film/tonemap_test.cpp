// The display transform's table of code thresholds against the definition it replaces
// (round(255 * sRGB(x)) with a pow per channel): searched over the floats of [0, 1] where a
// table can go wrong, next to every threshold, and on a dense stride between them.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "common/film/tonemap.h"

namespace pathfarm {
namespace {

constexpr uint32_t kOneBits = 0x3f800000u;  // 1.0f

// Every float whose code differs from the one below it: where the codes step.
std::vector<uint32_t> code_steps() {
    std::vector<uint32_t> steps;
    for (int c = 1; c < 256; ++c) {
        uint32_t lo = 0, hi = kOneBits;
        while (lo < hi) {
            const uint32_t mid = lo + (hi - lo) / 2;
            if (srgb8_reference(std::bit_cast<float>(mid)) >= c)
                hi = mid;
            else
                lo = mid + 1;
        }
        steps.push_back(lo);
    }
    return steps;
}

TEST(Tonemap, CodesEqualTheDefinitionAroundEveryStepAndAcrossTheUnitInterval) {
    int checked = 0, wrong = 0;
    const auto check = [&](uint32_t bits) {
        const float x = std::bit_cast<float>(bits);
        ++checked;
        if (int(srgb8_code(x)) != srgb8_reference(x) && ++wrong <= 5)
            ADD_FAILURE() << "display value " << x << " (bits " << bits << "): code "
                          << int(srgb8_code(x)) << ", definition " << srgb8_reference(x);
    };
    for (const uint32_t s : code_steps())
        for (uint32_t b = s - std::min(s, 4096u); b <= std::min(kOneBits, s + 4096u); ++b)
            check(b);
    for (uint32_t b = 0; b <= kOneBits; b += 257)
        check(b);
    EXPECT_EQ(wrong, 0) << "of " << checked;
    EXPECT_GT(checked, 4'000'000);
}

TEST(Tonemap, OutOfRangeAndNonFiniteValuesClampToTheEnds) {
    EXPECT_EQ(srgb8_code(-1.0f), 0);
    EXPECT_EQ(srgb8_code(0.0f), 0);
    EXPECT_EQ(srgb8_code(1.0f), 255);
    EXPECT_EQ(srgb8_code(2.0f), 255);
    EXPECT_EQ(srgb8_code(std::numeric_limits<float>::quiet_NaN()), 0);
    EXPECT_EQ(tonemap_channel(std::numeric_limits<float>::quiet_NaN()), 0);
    EXPECT_EQ(tonemap_channel(std::numeric_limits<float>::infinity()), 0);
    EXPECT_EQ(tonemap_channel(-5.0f), 0);
    EXPECT_EQ(tonemap_channel(1e30f), 255);  // a firefly is white, not black (x * x overflowed)
    EXPECT_EQ(tonemap_channel(1e30f, 1e30f), 255);
    EXPECT_EQ(tonemap_channel(std::numeric_limits<float>::max()), 255);
}

TEST(Tonemap, ImagesMapChannelByChannelWithExposure) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.5f, 4.0f);
    FloatImage img(17, 9);
    for (float& v : img.rgb)
        v = u(rng) * u(rng);
    img.rgb[5] = std::numeric_limits<float>::quiet_NaN();
    for (const float exposure : {1.0f, 0.25f, 3.0f}) {
        const std::vector<uint8_t> out = tonemap_to_srgb8(img, exposure);
        ASSERT_EQ(out.size(), img.rgb.size());
        for (std::size_t i = 0; i < out.size(); ++i)
            EXPECT_EQ(out[i], tonemap_channel(img.rgb[i], exposure)) << i;
    }
    EXPECT_EQ(tonemap_to_srgb8(img)[5], 0);
}

}  // namespace
}  // namespace pathfarm
