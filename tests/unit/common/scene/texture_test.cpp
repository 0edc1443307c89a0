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

// KHR_texture_transform: uv' = T * R * S * uv with R = [cos sin; -sin cos] (the spec's matrix).
TEST(UvTransform, FollowsTheSpecMatrix) {
    UvTransform t;
    EXPECT_TRUE(t.identity());
    EXPECT_EQ(t.apply(Vec2(0.3f, 0.7f)), Vec2(0.3f, 0.7f));
    t.offset = Vec2(0.5f, 0.25f);
    t.rotation = 0.5f * kPi;
    t.scale = Vec2(2.0f, 3.0f);
    // scale: (0.2, 0.6); rotate: (0.2 cos + 0.6 sin, -0.2 sin + 0.6 cos) = (0.6, -0.2); offset.
    const Vec2 uv = t.apply(Vec2(0.1f, 0.2f));
    EXPECT_NEAR(uv.x, 1.1f, 1e-6f);
    EXPECT_NEAR(uv.y, 0.05f, 1e-6f);
}

}  // namespace
}  // namespace pathfarm
