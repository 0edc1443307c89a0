// Image files: PFM here, JPEG textures through libturbojpeg (jpeg_codec.h), everything else
// through the OpenImageIO module (oiio_images.h), which is loaded the first time a process reads
// or writes such a file. Loading it costs 0.3-0.4 s (about 170 000 relocations against some
// 260 libraries): a scene whose textures are all JPEG (Sponza, the Damaged Helmet, Cesium Man)
// no longer pays it.
#include "common/film/image_io.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>

#include "common/film/jpeg_codec.h"
#include "common/film/oiio_images.h"
#include "common/film/pfm.h"
#include "common/film/tonemap.h"

namespace pathfarm {
namespace {

enum class ImageFormat { pfm, exr, srgb8, unknown };

// By extension, as write_image documents it.
ImageFormat format_of(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext == ".pfm") return ImageFormat::pfm;
    if (ext == ".exr") return ImageFormat::exr;
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") return ImageFormat::srgb8;
    return ImageFormat::unknown;
}

Error unknown_format(const std::string& path) {
    return make_error(ErrorCode::invalid_argument,
                      "{}: unknown image extension (use .exr, .pfm or .png)", path);
}

// Calls `call` with the OpenImageIO module's table, or returns why it could not be loaded.
template <typename Call>
auto through_module(Call&& call) -> decltype(call(std::declval<const OiioImages&>())) {
    const auto oiio = oiio_images();
    if (!oiio) return oiio.error();
    return call(**oiio);
}

// KTX2 (glTF's KHR_texture_basisu) has no decoder in this stack, OpenImageIO's included:
// loading the module only to hear that cost 0.3-0.4 s.
constexpr unsigned char kKtx2Identifier[12] = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                               '0',  0xBB, '\r', '\n', 0x1A, '\n'};

bool is_ktx2(const unsigned char* data, std::size_t size) {
    return size >= sizeof kKtx2Identifier &&
           std::equal(std::begin(kKtx2Identifier), std::end(kKtx2Identifier), data);
}

Error no_ktx2_decoder(const std::string& name) {
    return make_error(ErrorCode::unsupported, "{}: a KTX2 image, which nothing here decodes", name);
}

}  // namespace

Status write_image(const std::string& path, const FloatImage& image, float exposure) {
    switch (format_of(path)) {
        case ImageFormat::pfm:
            return write_pfm(path, image);
        case ImageFormat::exr:
            return through_module([&](const OiioImages& m) { return m.write_exr(path, image); });
        case ImageFormat::srgb8:
            return write_rgb8(path, image.width, image.height, tonemap_to_srgb8(image, exposure));
        case ImageFormat::unknown:
            break;
    }
    return unknown_format(path);
}

Status check_image_format(const std::string& path) {
    switch (format_of(path)) {
        case ImageFormat::pfm:
            return {};
        case ImageFormat::exr:
        case ImageFormat::srgb8:
            return through_module([](const OiioImages&) { return Status{}; });
        case ImageFormat::unknown:
            break;
    }
    return unknown_format(path);
}

Status write_rgb8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
    return through_module(
        [&](const OiioImages& m) { return m.write_rgb8(path, width, height, rgb); });
}

Result<std::vector<uint8_t>> encode_png(int width, int height, const std::vector<uint8_t>& rgb) {
    return through_module([&](const OiioImages& m) { return m.encode_png(width, height, rgb); });
}

Result<FloatImage> read_image(const std::string& path) {
    if (format_of(path) == ImageFormat::pfm) return read_pfm(path);
    return through_module([&](const OiioImages& m) { return m.read_image(path); });
}

Result<Rgba8Image> read_rgba8(const std::string& path) {
    if (std::ifstream in{path, std::ios::binary}) {
        unsigned char head[sizeof kKtx2Identifier] = {};
        in.read(reinterpret_cast<char*>(head), sizeof head);
        const auto got = std::size_t(in.gcount());
        if (is_ktx2(head, got)) return no_ktx2_decoder(path);
        if (looks_like_jpeg(head, got)) {
            in.clear();
            in.seekg(0);
            const std::vector<unsigned char> bytes{std::istreambuf_iterator<char>(in), {}};
            if (auto image = decode_jpeg_rgba8(bytes.data(), bytes.size()))
                return std::move(*image);
        }
    }  // a file that cannot be opened: the module's error names it, as before
    return through_module([&](const OiioImages& m) { return m.read_rgba8(path); });
}

Result<Rgba8Image> decode_rgba8(const unsigned char* data, std::size_t size,
                                const std::string& name_hint) {
    if (is_ktx2(data, size)) return no_ktx2_decoder(name_hint);
    if (auto image = decode_jpeg_rgba8(data, size)) return std::move(*image);
    return through_module(
        [&](const OiioImages& m) { return m.decode_rgba8(data, size, name_hint); });
}

}  // namespace pathfarm
