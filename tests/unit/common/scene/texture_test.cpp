// Texture lookups: glTF wrap modes, nearest vs linear filtering, sRGB decoding.
#include "common/scene/texture.h"

#include <gtest/gtest.h>

namespace pathfarm {
namespace {

Image two_by_one(uint8_t left, uint8_t right) {
    return Image{"t", 2, 1, {left, left, left, 255, right, right, right, 255}};
}

TEST(Texture, NearestPicksTexelsAndWraps) {
    const Image img = two_by_one(0, 255);
    Sampler s;
    s.filter = FilterMode::nearest;
    EXPECT_EQ(sample_image(&img, s, {0.25f, 0.5f}, false).x, 0.0f);
    EXPECT_EQ(sample_image(&img, s, {0.75f, 0.5f}, false).x, 1.0f);
    EXPECT_EQ(sample_image(&img, s, {1.25f, 0.5f}, false).x, 0.0f);  // repeat
    s.wrap_s = WrapMode::clamp_to_edge;
    EXPECT_EQ(sample_image(&img, s, {1.25f, 0.5f}, false).x, 1.0f);
    s.wrap_s = WrapMode::mirrored_repeat;
    EXPECT_EQ(sample_image(&img, s, {1.25f, 0.5f}, false).x, 1.0f);
    EXPECT_EQ(sample_image(&img, s, {1.75f, 0.5f}, false).x, 0.0f);
}

TEST(Texture, LinearInterpolatesBetweenTexelCentres) {
    const Image img = two_by_one(0, 255);
    Sampler s;
    s.wrap_s = WrapMode::clamp_to_edge;
    EXPECT_NEAR(sample_image(&img, s, {0.5f, 0.5f}, false).x, 0.5f, 1e-6f);
    EXPECT_NEAR(sample_image(&img, s, {0.25f, 0.5f}, false).x, 0.0f, 1e-6f);
}

TEST(Texture, SrgbDecodingAndMissingImage) {
    const Image img = two_by_one(128, 128);
    Sampler s;
    EXPECT_NEAR(sample_image(&img, s, {0.5f, 0.5f}, true).x, 0.2158f, 1e-3f);
    EXPECT_NEAR(sample_image(&img, s, {0.5f, 0.5f}, false).x, 128.0f / 255.0f, 1e-6f);
    EXPECT_EQ(sample_image(nullptr, s, {0.5f, 0.5f}, true), Vec4(1.0f));
    EXPECT_EQ(sample_image(&img, s, {NAN, 0.5f}, true), Vec4(1.0f));
    EXPECT_NEAR(linear_to_srgb(srgb_to_linear(0.3f)), 0.3f, 1e-5f);
}

}  // namespace
}  // namespace pathfarm
