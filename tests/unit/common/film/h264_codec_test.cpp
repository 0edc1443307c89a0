// H.264 through libavcodec/libx264: a moving picture round-trips at a PSNR worth watching, IDR
// frames come first, when asked for and every key interval, and only then; bad input is an
// error, never a crash.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/film/h264_codec.h"
#include "common/film/image_compare.h"

namespace pathfarm {
namespace {

// A smooth picture with a bright disc moving across it: what inter prediction is for.
std::vector<uint8_t> moving_picture(int w, int h, int t) {
    std::vector<uint8_t> rgb(std::size_t(w) * h * 3);
    const double cx = 20.0 + 3.0 * t, cy = h / 2.0 + 10.0 * std::sin(0.3 * t);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool disc = (x - cx) * (x - cx) + (y - cy) * (y - cy) < 144.0;
            uint8_t* p = &rgb[3 * (std::size_t(y) * w + x)];
            p[0] = disc ? 240 : uint8_t(40 + 150 * x / w);
            p[1] = disc ? 200 : uint8_t(60 + 120 * y / h);
            p[2] = disc ? 30 : uint8_t(90 + ((x / 16 + y / 16) % 2) * 60);
        }
    return rgb;
}

TEST(H264Codec, MovingPictureRoundTripsWithIdrFramesOnlyWhereDue) {
    const int w = 160, h = 90;
    auto encoder = H264Encoder::open({w, h, 10.0, 12, 20, 1, "ultrafast"});
    ASSERT_TRUE(encoder) << encoder.error().message;
    auto decoder = H264Decoder::open();
    ASSERT_TRUE(decoder) << decoder.error().message;
    std::size_t key_bytes = 0, delta_bytes = 0;
    for (int t = 0; t < 30; ++t) {
        const auto rgb = moving_picture(w, h, t);
        const bool forced = t == 17;
        auto picture = (*encoder)->encode(rgb, forced);
        ASSERT_TRUE(picture) << picture.error().message;
        ASSERT_FALSE(picture->bytes.empty());
        // Every 12 frames, and the forced one restarts the count: 0, 12, 17, 17 + 12.
        EXPECT_EQ(picture->key, t == 0 || t == 12 || t == 17 || t == 29) << t;
        (picture->key ? key_bytes : delta_bytes) += picture->bytes.size();
        auto shown = (*decoder)->decode(picture->bytes);
        ASSERT_TRUE(shown) << t << ": " << shown.error().message;
        ASSERT_EQ(shown->width, w);
        ASSERT_EQ(shown->height, h);
        EXPECT_GT(psnr8(shown->rgb, rgb), 33.0) << t;
    }
    EXPECT_LT(delta_bytes / 26, key_bytes / 4 / 2);  // predicted frames cost less
}

TEST(H264Codec, ADecoderJoiningAtAnIdrFrameShowsTheStream) {
    const int w = 64, h = 48;
    auto encoder = H264Encoder::open({w, h, 30.0, 1000, 23, 2, "ultrafast"});  // sliced threads
    ASSERT_TRUE(encoder) << encoder.error().message;
    for (int t = 0; t < 5; ++t)
        ASSERT_TRUE((*encoder)->encode(moving_picture(w, h, t), false));
    auto late = H264Decoder::open();
    ASSERT_TRUE(late);
    auto idr = (*encoder)->encode(moving_picture(w, h, 5), true);
    ASSERT_TRUE(idr && idr->key);
    ASSERT_TRUE((*late)->decode(idr->bytes));  // SPS and PPS come with every IDR frame
    auto next = (*encoder)->encode(moving_picture(w, h, 6), false);
    ASSERT_TRUE(next && !next->key);
    auto shown = (*late)->decode(next->bytes);
    ASSERT_TRUE(shown) << shown.error().message;
    EXPECT_GT(psnr8(shown->rgb, moving_picture(w, h, 6)), 27.0);
}

TEST(H264Codec, BadSettingsAndInputsAreErrors) {
    EXPECT_FALSE(H264Encoder::open({161, 90, 10.0, 12, 23, 1, "ultrafast"}));
    EXPECT_FALSE(H264Encoder::open({160, 90, 10.0, 12, 60, 1, "ultrafast"}));
    EXPECT_FALSE(H264Encoder::open({160, 90, 10.0, 12, 23, 1, "warp-speed"}));
    auto encoder = H264Encoder::open({160, 90, 10.0, 12, 23, 1, "ultrafast"});
    ASSERT_TRUE(encoder);
    EXPECT_FALSE((*encoder)->encode(std::vector<uint8_t>(100), false));
    auto decoder = H264Decoder::open();
    ASSERT_TRUE(decoder);
    std::mt19937 rng(7);
    for (int trial = 0; trial < 50; ++trial) {  // garbage: errors, never a crash
        std::string bytes(rng() % 400, '\0');
        for (char& c : bytes)
            c = char(rng());
        (void)(*decoder)->decode(bytes);
    }
}

// A rendered frame's colours vary from pixel to pixel (lights of several colours, residual
// noise). Near-lossless, what is left is the RGB <-> YUV 4:2:0 round trip: 34.7 dB here with
// exact rounding and full-resolution chroma interpolation, 21.4 dB with the conversions' fast
// paths (2.5 dB less on the demo's frames, a cost every bit rate paid).
TEST(H264Codec, NearLosslessStreamKeepsColourDetail) {
    const int w = 96, h = 64;
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> luma_grain(-10, 10), chroma_grain(-3, 3);
    H264Settings settings = h264_stream_settings(w, h);
    settings.crf = 1;
    auto encoder = H264Encoder::open(settings);
    ASSERT_TRUE(encoder) << encoder.error().message;
    auto decoder = H264Decoder::open();
    ASSERT_TRUE(decoder);
    for (int t = 0; t < 4; ++t) {
        std::vector<uint8_t> rgb(std::size_t(w) * h * 3);
        for (int y = 0; y < h; ++y)  // hues turning every few pixels, grain mostly in luma
            for (int x = 0; x < w; ++x) {
                const int grain = luma_grain(rng);
                for (int c = 0; c < 3; ++c) {
                    const double hue = std::sin(0.7 * x + 0.45 * y + 2.1 * c + 0.3 * t);
                    rgb[3 * (std::size_t(y) * w + x) + c] = uint8_t(
                        std::clamp(120 + int(70.0 * hue) + grain + chroma_grain(rng), 0, 255));
                }
            }
        auto picture = (*encoder)->encode(rgb, false);
        ASSERT_TRUE(picture) << picture.error().message;
        auto shown = (*decoder)->decode(picture->bytes);
        ASSERT_TRUE(shown) << shown.error().message;
        EXPECT_GT(psnr8(shown->rgb, rgb), 32.0) << t;
    }
}

TEST(H264Codec, UnknownX264OptionIsAnErrorNamingIt) {
    H264Settings settings = h264_stream_settings(160, 90);
    settings.x264_params = "no-such-option=3";
    auto encoder = H264Encoder::open(settings);
    ASSERT_FALSE(encoder);
    EXPECT_NE(encoder.error().message.find("no-such-option"), std::string::npos)
        << encoder.error().message;
}

TEST(H264Codec, PsnrOfIdenticalAndOffByOneBytes) {
    const std::vector<uint8_t> a(300, 100), b(300, 101);
    EXPECT_TRUE(std::isinf(psnr8(a, a)));
    EXPECT_NEAR(psnr8(a, b), 10.0 * std::log10(255.0 * 255.0), 1e-9);
}

}  // namespace
}  // namespace pathfarm
