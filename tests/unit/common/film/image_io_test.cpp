// Image files: EXR and PFM round-trip linear float exactly; PNG is tonemapped; errors name files.
#include "common/film/image_io.h"

#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "common/film/image_compare.h"
#include "tests/support/test_env.h"

namespace pathfarm::image_io_test {
namespace {

FloatImage gradient() {
    FloatImage img(7, 5);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x)
            img.set_pixel(x, y, Rgb(0.1f * x, 0.37f * y, 123.5f));
    return img;
}

TEST(ImageIo, FloatFormatsRoundTripExactly) {
    const std::string dir = test::scratch_dir();
    const FloatImage img = gradient();
    for (const char* name : {"/a.exr", "/a.pfm"}) {
        ASSERT_TRUE(write_image(dir + name, img).ok());
        auto back = read_image(dir + name);
        ASSERT_TRUE(back.ok()) << back.error().message;
        ASSERT_EQ(back->width, 7);
        EXPECT_EQ(back->rgb, img.rgb) << name << " keeps row 0 at the top and full precision";
    }
}

TEST(ImageIo, FloatTexturesWithNanAndInfDecodeToDefinedBytes) {
    FloatImage img(2, 2);
    img.set_pixel(0, 0, Rgb(std::nanf(""), 0.5f, 1.0f));
    img.set_pixel(1, 0, Rgb(INFINITY, -INFINITY, 0.0f));
    img.set_pixel(0, 1, Rgb(2.0f, -1.0f, 0.25f));
    img.set_pixel(1, 1, Rgb(std::nanf(""), std::nanf(""), std::nanf("")));
    const std::string path = test::scratch_dir() + "/nan.exr";
    ASSERT_TRUE(write_image(path, img).ok());
    auto decoded = read_rgba8(path);
    ASSERT_TRUE(decoded.ok()) << decoded.error().message;
    EXPECT_EQ(decoded->nonfinite_values, 6u);
    const std::vector<uint8_t> expected = {0,   128, 255, 255, 255, 0, 0, 255,
                                           255, 0,   64,  255, 0,   0, 0, 255};
    EXPECT_EQ(decoded->rgba, expected);
}

TEST(ImageIo, PngIsWrittenAndBadPathsAreErrors) {
    const std::string dir = test::scratch_dir();
    EXPECT_TRUE(write_image(dir + "/a.png", gradient()).ok());
    EXPECT_FALSE(write_image(dir + "/a.xyz", gradient()).ok());
    const auto missing = read_image(dir + "/none.exr");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("none.exr"), std::string::npos);
}

// KTX2 has no decoder here (nor in OpenImageIO): a one-line error naming the image, from the
// file's identifier, whatever its name or extension.
TEST(ImageIo, Ktx2IsAnErrorNamingTheImage) {
    const unsigned char ktx2[16] = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                    '0',  0xBB, '\r', '\n', 0x1A, '\n'};
    const auto decoded = decode_rgba8(ktx2, sizeof ktx2, "lamp_normal.png");
    ASSERT_FALSE(decoded.ok());
    EXPECT_NE(decoded.error().message.find("lamp_normal.png: a KTX2 image"), std::string::npos)
        << decoded.error().message;
    const std::string path = test::scratch_dir() + "/texture.bin";
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(ktx2), sizeof ktx2);
    const auto read = read_rgba8(path);
    ASSERT_FALSE(read.ok());
    EXPECT_NE(read.error().message.find(path + ": a KTX2 image"), std::string::npos)
        << read.error().message;
    EXPECT_EQ(read.error().message.find('\n'), std::string::npos);
}

TEST(ImageCompare, RmseAndRelativeMse) {
    FloatImage a(2, 1), b(2, 1);
    b.rgb = {1, 1, 1, 1, 1, 1};
    EXPECT_NEAR(rmse(a, b), 1.0, 1e-12);
    EXPECT_NEAR(relative_mse(a, b, 0.0), 1.0, 1e-12);
    EXPECT_EQ(rmse(b, b), 0.0);
}

}  // namespace
}  // namespace pathfarm::image_io_test
