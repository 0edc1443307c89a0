// Image files: PFM here, everything else through the OpenImageIO module (oiio_images.h), which
// is loaded the first time a process reads or writes such a file.
#include "common/film/image_io.h"

#include <algorithm>
#include <filesystem>

#include "common/film/oiio_images.h"
#include "common/film/pfm.h"
#include "common/film/tonemap.h"

namespace pathfarm {
namespace {

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    return ext;
}

}  // namespace

Status write_image(const std::string& path, const FloatImage& image, float exposure) {
    const std::string ext = lower_extension(path);
    if (ext == ".pfm") return write_pfm(path, image);
    if (ext == ".exr") {
        const auto oiio = oiio_images();
        if (!oiio) return oiio.error();
        return (*oiio)->write_exr(path, image);
    }
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg")
        return write_rgb8(path, image.width, image.height, tonemap_to_srgb8(image, exposure));
    return make_error(ErrorCode::invalid_argument,
                      "{}: unknown image extension (use .exr, .pfm or .png)", path);
}

Status check_image_format(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".pfm") return {};
    if (ext == ".exr" || ext == ".png" || ext == ".jpg" || ext == ".jpeg") {
        const auto oiio = oiio_images();
        if (!oiio) return oiio.error();
        return {};
    }
    return make_error(ErrorCode::invalid_argument,
                      "{}: unknown image extension (use .exr, .pfm or .png)", path);
}

Status write_rgb8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
    const auto oiio = oiio_images();
    if (!oiio) return oiio.error();
    return (*oiio)->write_rgb8(path, width, height, rgb);
}

Result<std::vector<uint8_t>> encode_png(int width, int height, const std::vector<uint8_t>& rgb) {
    const auto oiio = oiio_images();
    if (!oiio) return oiio.error();
    return (*oiio)->encode_png(width, height, rgb);
}

Result<FloatImage> read_image(const std::string& path) {
    if (lower_extension(path) == ".pfm") return read_pfm(path);
    const auto oiio = oiio_images();
    if (!oiio) return oiio.error();
    return (*oiio)->read_image(path);
}

Result<Rgba8Image> read_rgba8(const std::string& path) {
    const auto oiio = oiio_images();
    if (!oiio) return oiio.error();
    return (*oiio)->read_rgba8(path);
}

Result<Rgba8Image> decode_rgba8(const unsigned char* data, std::size_t size,
                                const std::string& name_hint) {
    const auto oiio = oiio_images();
    if (!oiio) return oiio.error();
    return (*oiio)->decode_rgba8(data, size, name_hint);
}

}  // namespace pathfarm
