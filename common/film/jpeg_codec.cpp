// libturbojpeg's TurboJPEG API (tjInitCompress / tjCompress2 / tjDecompress2).
#include "common/film/jpeg_codec.h"

#include <memory>

#include <turbojpeg.h>

namespace pathfarm {
namespace {

struct HandleCloser {
    void operator()(void* h) const { tjDestroy(h); }
};
using Handle = std::unique_ptr<void, HandleCloser>;

constexpr std::size_t kMaxTexturePixels = std::size_t(1) << 28;  // 16384 x 16384, 1 GiB of RGBA

}  // namespace

Result<std::string> encode_jpeg(int width, int height, const std::vector<uint8_t>& rgb,
                                int quality) {
    if (width <= 0 || height <= 0 || rgb.size() != std::size_t(width) * height * 3)
        return make_error(ErrorCode::invalid_argument, "JPEG encode: {}x{} image with {} bytes",
                          width, height, rgb.size());
    if (quality < 1 || quality > 100)
        return make_error(ErrorCode::invalid_argument, "JPEG quality {}: must be in [1, 100]",
                          quality);
    Handle h(tjInitCompress());
    if (!h) return make_error(ErrorCode::io_error, "JPEG encode: {}", tjGetErrorStr2(nullptr));
    unsigned char* out = nullptr;  // allocated by TurboJPEG, freed with tjFree
    unsigned long size = 0;
    if (tjCompress2(h.get(), rgb.data(), width, 0, height, TJPF_RGB, &out, &size, TJSAMP_420,
                    quality, TJFLAG_FASTDCT) != 0) {
        std::string why = tjGetErrorStr2(h.get());
        tjFree(out);
        return make_error(ErrorCode::io_error, "JPEG encode: {}", why);
    }
    std::string bytes(reinterpret_cast<const char*>(out), size);
    tjFree(out);
    return bytes;
}

Result<Rgb8Image> decode_jpeg(const std::string& bytes) {
    Handle h(tjInitDecompress());
    if (!h) return make_error(ErrorCode::io_error, "JPEG decode: {}", tjGetErrorStr2(nullptr));
    int width = 0, height = 0, subsampling = 0, colorspace = 0;
    auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    if (tjDecompressHeader3(h.get(), data, static_cast<unsigned long>(bytes.size()), &width,
                            &height, &subsampling, &colorspace) != 0)
        return make_error(ErrorCode::parse_error, "JPEG decode: {}", tjGetErrorStr2(h.get()));
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
        return make_error(ErrorCode::parse_error, "JPEG decode: {}x{} is not a frame size", width,
                          height);
    Rgb8Image img{width, height, std::vector<uint8_t>(std::size_t(width) * height * 3)};
    if (tjDecompress2(h.get(), data, static_cast<unsigned long>(bytes.size()), img.rgb.data(),
                      width, 0, height, TJPF_RGB, TJFLAG_FASTDCT) != 0)
        return make_error(ErrorCode::parse_error, "JPEG decode: {}", tjGetErrorStr2(h.get()));
    return img;
}

bool looks_like_jpeg(const unsigned char* data, std::size_t size) {
    return size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF;
}

std::optional<Rgba8Image> decode_jpeg_rgba8(const unsigned char* data, std::size_t size) {
    if (!looks_like_jpeg(data, size)) return std::nullopt;
    Handle h(tjInitDecompress());
    if (!h) return std::nullopt;
    int width = 0, height = 0, subsampling = 0, colorspace = 0;
    const auto bytes = static_cast<unsigned long>(size);
    // Past kMaxTexturePixels OpenImageIO decides too, as before (a damaged header can claim
    // 65535 x 65535: 17 GB of RGBA).
    if (tjDecompressHeader3(h.get(), data, bytes, &width, &height, &subsampling, &colorspace) !=
            0 ||
        width <= 0 || height <= 0 || std::size_t(width) * std::size_t(height) > kMaxTexturePixels ||
        colorspace == TJCS_CMYK || colorspace == TJCS_YCCK)
        return std::nullopt;
    Rgba8Image img{width, height, std::vector<uint8_t>(std::size_t(width) * height * 4), 0};
    // Flags 0: TJFLAG_FASTDCT and TJFLAG_FASTUPSAMPLE would give other bytes than OpenImageIO.
    // A warning (a truncated or damaged file) fails too: OpenImageIO then decides, as before.
    if (tjDecompress2(h.get(), data, bytes, img.rgba.data(), width, 0, height, TJPF_RGBA, 0) != 0)
        return std::nullopt;
    return img;
}

}  // namespace pathfarm
