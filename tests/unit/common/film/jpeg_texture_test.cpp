// JPEG textures through libturbojpeg (jpeg_codec.h) instead of the OpenImageIO module: the same
// bytes as OpenImageIO gives, for every JPEG of the shared scenes and for random images in every
// chroma subsampling and quality; what TurboJPEG cannot decode cleanly (CMYK, a truncated file,
// a header claiming more than 2^28 pixels) is left to OpenImageIO, which answers as before.
#include <sys/resource.h>
#include <turbojpeg.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include <gtest/gtest.h>

#include "common/film/image_io.h"
#include "common/film/jpeg_codec.h"
#include "common/film/oiio_images.h"
#include "tests/support/test_env.h"

namespace pathfarm::jpeg_texture_test {
namespace {

std::vector<unsigned char> file_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

const OiioImages& module() {
    static const auto images = oiio_images();
    EXPECT_TRUE(images.ok()) << images.error().message;
    return **images;
}

// Encodes pixels (TJPF_RGB, TJPF_GRAY or TJPF_CMYK) with TurboJPEG's encoder.
std::vector<unsigned char> encode(const std::vector<unsigned char>& pixels, int w, int h,
                                  TJPF format, TJSAMP subsampling, int quality) {
    tjhandle handle = tjInitCompress();
    unsigned char* out = nullptr;
    unsigned long size = 0;
    const int failed =
        tjCompress2(handle, pixels.data(), w, 0, h, format, &out, &size, subsampling, quality, 0);
    std::vector<unsigned char> bytes;
    if (failed == 0) bytes.assign(out, out + size);
    tjFree(out);
    tjDestroy(handle);
    EXPECT_EQ(failed, 0) << "encoding the test image";
    return bytes;
}

void expect_same_pixels(const Rgba8Image& ours, const Rgba8Image& theirs, const std::string& what) {
    ASSERT_EQ(ours.width, theirs.width) << what;
    ASSERT_EQ(ours.height, theirs.height) << what;
    const auto diff = std::mismatch(ours.rgba.begin(), ours.rgba.end(), theirs.rgba.begin());
    EXPECT_TRUE(diff.first == ours.rgba.end())
        << what << ": first difference at byte " << (diff.first - ours.rgba.begin()) << " of "
        << ours.rgba.size();
}

TEST(JpegTexture, EveryJpegOfTheSharedScenesDecodesAsOpenImageIoDecodesIt) {
    PF_REQUIRE_SCENES(scenes);
    int files = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(scenes)) {
        std::string ext = entry.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
        if (!entry.is_regular_file() || (ext != ".jpg" && ext != ".jpeg")) continue;
        const std::vector<unsigned char> bytes = file_bytes(entry.path());
        const auto ours = decode_jpeg_rgba8(bytes.data(), bytes.size());
        ASSERT_TRUE(ours.has_value()) << entry.path() << ": TurboJPEG left it to OpenImageIO";
        const auto theirs = module().read_rgba8(entry.path().string());
        ASSERT_TRUE(theirs.ok()) << theirs.error().message;
        expect_same_pixels(*ours, *theirs, entry.path().string());
        // read_rgba8, the loaders' way in, takes the same path.
        const auto read = read_rgba8(entry.path().string());
        ASSERT_TRUE(read.ok()) << read.error().message;
        expect_same_pixels(*read, *theirs, entry.path().string() + " (read_rgba8)");
        ++files;
    }
    EXPECT_GE(files, 30) << "the shared scenes hold 32 JPEG textures";
}

TEST(JpegTexture, RandomImagesInEverySubsamplingDecodeAsOpenImageIoDecodesThem) {
    std::mt19937 rng(20261207);
    const TJSAMP subsamplings[] = {TJSAMP_444, TJSAMP_422, TJSAMP_420,
                                   TJSAMP_440, TJSAMP_411, TJSAMP_GRAY};
    for (int trial = 0; trial < 60; ++trial) {
        const int w = std::uniform_int_distribution<int>(1, 97)(rng);
        const int h = std::uniform_int_distribution<int>(1, 61)(rng);
        const TJSAMP sub = subsamplings[trial % std::size(subsamplings)];
        const int quality = std::uniform_int_distribution<int>(5, 100)(rng);
        // Smooth colour with noise and a hard edge: chroma upsampling shows at both.
        std::vector<unsigned char> rgb(std::size_t(w) * h * 3);
        std::uniform_int_distribution<int> noise(-20, 20);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) {
                    const int base = (x * 255 / w + c * 80 + (x > w / 2 ? 120 : 0)) % 256;
                    rgb[(std::size_t(y) * w + x) * 3 + c] =
                        uint8_t(std::clamp(base + noise(rng), 0, 255));
                }
        const auto bytes =
            sub == TJSAMP_GRAY
                ? encode(std::vector<unsigned char>(rgb.begin(), rgb.begin() + rgb.size() / 3), w,
                         h, TJPF_GRAY, sub, quality)
                : encode(rgb, w, h, TJPF_RGB, sub, quality);
        const std::string what = "trial " + std::to_string(trial) + " (" + std::to_string(w) + "x" +
                                 std::to_string(h) + ", subsampling " + std::to_string(int(sub)) +
                                 ", quality " + std::to_string(quality) + ")";
        const auto ours = decode_jpeg_rgba8(bytes.data(), bytes.size());
        ASSERT_TRUE(ours.has_value()) << what;
        const auto theirs = module().decode_rgba8(bytes.data(), bytes.size(), "t.jpg");
        ASSERT_TRUE(theirs.ok()) << what << ": " << theirs.error().message;
        expect_same_pixels(*ours, *theirs, what);
    }
}

TEST(JpegTexture, CmykTruncatedAndOversizedFilesAreLeftToOpenImageIo) {
    const int w = 24, h = 16;
    std::vector<unsigned char> cmyk(std::size_t(w) * h * 4);
    for (std::size_t i = 0; i < cmyk.size(); ++i)
        cmyk[i] = uint8_t(i * 37 % 251);
    const auto cmyk_jpeg = encode(cmyk, w, h, TJPF_CMYK, TJSAMP_444, 90);
    EXPECT_FALSE(decode_jpeg_rgba8(cmyk_jpeg.data(), cmyk_jpeg.size()).has_value());
    const auto via_module = module().decode_rgba8(cmyk_jpeg.data(), cmyk_jpeg.size(), "c.jpg");
    const auto through_api = decode_rgba8(cmyk_jpeg.data(), cmyk_jpeg.size(), "c.jpg");
    ASSERT_EQ(via_module.ok(), through_api.ok());
    if (via_module.ok()) expect_same_pixels(*through_api, *via_module, "CMYK");

    std::vector<unsigned char> rgb(std::size_t(w) * h * 3, 128);
    const auto whole = encode(rgb, w, h, TJPF_RGB, TJSAMP_420, 90);
    const std::vector<unsigned char> cut(whole.begin(), whole.begin() + whole.size() / 2);
    EXPECT_FALSE(decode_jpeg_rgba8(cut.data(), cut.size()).has_value());
    const auto cut_module = module().decode_rgba8(cut.data(), cut.size(), "t.jpg");
    const auto cut_api = decode_rgba8(cut.data(), cut.size(), "t.jpg");
    EXPECT_EQ(cut_module.ok(), cut_api.ok());

    // A header claiming 20000 x 20000 pixels (a damaged or hostile file): left to OpenImageIO
    // before anything is allocated for it (1.6 GB of RGBA; the process's peak memory shows it).
    std::vector<unsigned char> huge = whole;
    const unsigned char sof0[] = {0xFF, 0xC0};
    const auto sof = std::search(huge.begin(), huge.end(), std::begin(sof0), std::end(sof0));
    ASSERT_NE(sof, huge.end()) << "a baseline JPEG has an SOF0 marker";
    const std::size_t at = std::size_t(sof - huge.begin()) + 5;  // height, then width, big-endian
    for (int k = 0; k < 4; ++k)
        huge[at + k] = k % 2 == 0 ? 0x4E : 0x20;  // 0x4E20 = 20000
    rusage before{}, after{};
    getrusage(RUSAGE_SELF, &before);
    EXPECT_FALSE(decode_jpeg_rgba8(huge.data(), huge.size()).has_value());
    getrusage(RUSAGE_SELF, &after);
    EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 100 * 1024) << "kB of peak memory";

    const unsigned char png_start[] = {0x89, 'P', 'N', 'G'};
    EXPECT_FALSE(looks_like_jpeg(png_start, sizeof png_start));
    EXPECT_FALSE(decode_jpeg_rgba8(png_start, sizeof png_start).has_value());
}

}  // namespace
}  // namespace pathfarm::jpeg_texture_test
