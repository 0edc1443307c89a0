// JPEG frames through libturbojpeg: a round trip stays close, bad input fails cleanly.
#include <gtest/gtest.h>

#include "common/film/jpeg_codec.h"

namespace pathfarm::jpeg_codec_test {
namespace {

std::vector<uint8_t> gradient(int w, int h) {
    std::vector<uint8_t> rgb(std::size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            uint8_t* p = &rgb[(std::size_t(y) * w + x) * 3];
            p[0] = uint8_t(255 * x / (w - 1));
            p[1] = uint8_t(255 * y / (h - 1));
            p[2] = uint8_t(64 + 127 * (x + y) / (w + h));  // smooth, like a rendered frame
        }
    return rgb;
}

TEST(JpegCodec, RoundTripIsCloseAndSmall) {
    const int w = 160, h = 90;
    const auto rgb = gradient(w, h);
    auto bytes = encode_jpeg(w, h, rgb, 90);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message;
    EXPECT_LT(bytes->size(), rgb.size() / 4);
    auto back = decode_jpeg(*bytes);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->width, w);
    ASSERT_EQ(back->height, h);
    double sum = 0.0;
    for (std::size_t i = 0; i < rgb.size(); ++i)
        sum += (double(rgb[i]) - back->rgb[i]) * (double(rgb[i]) - back->rgb[i]);
    const double psnr = 10.0 * std::log10(255.0 * 255.0 / (sum / double(rgb.size())));
    EXPECT_GT(psnr, 35.0);
}

TEST(JpegCodec, BadInputIsAnError) {
    EXPECT_FALSE(encode_jpeg(4, 4, std::vector<uint8_t>(10), 90).ok());
    EXPECT_FALSE(encode_jpeg(4, 4, std::vector<uint8_t>(48), 0).ok());
    EXPECT_FALSE(decode_jpeg("not a jpeg").ok());
    auto bytes = encode_jpeg(16, 16, gradient(16, 16), 80);
    ASSERT_TRUE(bytes.ok());
    EXPECT_FALSE(decode_jpeg(bytes->substr(0, bytes->size() / 3)).ok()) << "truncated";
}

}  // namespace
}  // namespace pathfarm::jpeg_codec_test
