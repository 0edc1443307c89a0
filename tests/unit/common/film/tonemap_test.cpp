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

// The image path works on runs of floats (the fit vectorised, then the table): over several
// runs, with every kind of float at random places among them, it still gives each channel's
// own code.
TEST(Tonemap, RunsOfAnyFloatsMapAsEachChannelAlone) {
    std::mt19937 rng(11);
    const float specials[] = {std::numeric_limits<float>::quiet_NaN(),
                              -std::numeric_limits<float>::quiet_NaN(),
                              std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(),
                              std::numeric_limits<float>::max(),
                              -std::numeric_limits<float>::max(),
                              std::numeric_limits<float>::denorm_min(),
                              std::numeric_limits<float>::min(),
                              -0.0f,
                              0.0f,
                              1e6f,
                              1.0000001e6f,
                              1e19f,
                              1.0f};
    std::uniform_real_distribution<float> log10(-8.0f, 8.0f), u(0.0f, 1.0f);
    std::uniform_int_distribution<int> special(0, int(std::size(specials)) - 1);
    FloatImage img(641, 3);  // 5769 floats: runs and a partial one
    for (float& v : img.rgb)
        v = u(rng) < 0.1f ? specials[special(rng)]
                          : (u(rng) < 0.2f ? -1.0f : 1.0f) * std::pow(10.0f, log10(rng));
    for (const float exposure : {1.0f, 0.01f, 7.5f, 1e20f}) {
        const std::vector<uint8_t> out = tonemap_to_srgb8(img, exposure);
        ASSERT_EQ(out.size(), img.rgb.size());
        int wrong = 0;
        for (std::size_t i = 0; i < out.size(); ++i)
            wrong += out[i] != tonemap_channel(img.rgb[i], exposure);
        EXPECT_EQ(wrong, 0) << "exposure " << exposure;
    }
}

}  // namespace
}  // namespace pathfarm
