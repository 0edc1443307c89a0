// The OpenImageIO module (oiio_images.h): every codec that needs OIIO, behind one exported
// table. Built as libpathfarm_oiio.so and loaded by image_io.cpp on first use.
#include <algorithm>
#include <cmath>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "common/film/oiio_images.h"

namespace pathfarm {
namespace {

Status write_with_oiio(const std::string& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                       const void* data) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out)
        return make_error(ErrorCode::io_error, "{}: cannot write this format ({})", path,
                          OIIO::geterror());
    if (!out->open(path, spec) || !out->write_image(type, data) || !out->close())
        return make_error(ErrorCode::io_error, "{}: {}", path, out->geterror());
    return {};
}

// Texture reads keep colour and alpha apart: glTF colour is unassociated (straight) alpha,
// while OIIO by default multiplies colour by alpha when it reads a PNG, which turned the RGB
// under transparent texels black (the Khronos AlphaBlendModeTest's OPAQUE check mark).
const OIIO::ImageSpec& texture_read_config() {
    static const OIIO::ImageSpec config = [] {
        OIIO::ImageSpec c;
        c.attribute("oiio:UnassociatedAlpha", 1);
        return c;
    }();
    return config;
}

Result<Rgba8Image> read_rgba8_from(std::unique_ptr<OIIO::ImageInput> in, const std::string& name) {
    if (!in)
        return make_error(ErrorCode::parse_error, "{}: cannot decode image ({})", name,
                          OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        return make_error(ErrorCode::parse_error, "{}: empty image", name);
    const std::size_t count = std::size_t(spec.width) * spec.height * spec.nchannels;
    std::vector<uint8_t> pixels(count);
    std::size_t nonfinite = 0;
    if (spec.format.is_floating_point()) {
        // Converted here rather than by OIIO: a NaN texel must become a defined value.
        std::vector<float> values(count);
        if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, values.data()))
            return make_error(ErrorCode::parse_error, "{}: {}", name, in->geterror());
        for (std::size_t i = 0; i < count; ++i) {
            float v = values[i];
            if (!std::isfinite(v)) {
                ++nonfinite;
                v = v > 0.0f ? 1.0f : 0.0f;  // NaN compares false: 0
            }
            pixels[i] = uint8_t(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
        }
    } else if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels.data())) {
        return make_error(ErrorCode::parse_error, "{}: {}", name, in->geterror());
    }
    Rgba8Image img{spec.width, spec.height,
                   std::vector<uint8_t>(std::size_t(spec.width) * spec.height * 4), nonfinite};
    const int nc = spec.nchannels;
    for (std::size_t i = 0; i < std::size_t(spec.width) * spec.height; ++i) {
        const uint8_t* src = &pixels[i * nc];
        uint8_t* dst = &img.rgba[i * 4];
        dst[0] = src[0];
        dst[1] = nc >= 3 ? src[1] : src[0];
        dst[2] = nc >= 3 ? src[2] : src[0];
        dst[3] = nc == 4 ? src[3] : (nc == 2 ? src[1] : 255);
    }
    return img;
}

Status write_exr_oiio(const std::string& path, const FloatImage& image) {
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "zip");
    return write_with_oiio(path, spec, OIIO::TypeDesc::FLOAT, image.rgb.data());
}

Status write_rgb8_oiio(const std::string& path, int width, int height,
                       const std::vector<uint8_t>& rgb) {
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    return write_with_oiio(path, spec, OIIO::TypeDesc::UINT8, rgb.data());
}

Result<std::vector<uint8_t>> encode_png_oiio(int width, int height,
                                             const std::vector<uint8_t>& rgb) {
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput vec(bytes);
    auto out = OIIO::ImageOutput::create("frame.png");
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    if (!out || !out->set_ioproxy(&vec) || !out->open("frame.png", spec) ||
        !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) || !out->close())
        return make_error(ErrorCode::io_error, "PNG encoding failed: {}",
                          out ? out->geterror() : OIIO::geterror());
    return std::vector<uint8_t>(bytes.begin(), bytes.end());
}

Result<FloatImage> read_image_oiio(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in)
        return make_error(ErrorCode::not_found, "{}: cannot open image ({})", path,
                          OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> pixels(std::size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()))
        return make_error(ErrorCode::parse_error, "{}: {}", path, in->geterror());
    const bool srgb = spec.format == OIIO::TypeDesc::UINT8;
    FloatImage img(spec.width, spec.height);
    for (std::size_t i = 0; i < std::size_t(spec.width) * spec.height; ++i)
        for (int c = 0; c < 3; ++c) {
            const float v = pixels[i * spec.nchannels + std::min(c, spec.nchannels - 1)];
            img.rgb[i * 3 + c] =
                srgb ? (v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f)) : v;
        }
    return img;
}

Result<Rgba8Image> read_rgba8_oiio(const std::string& path) {
    return read_rgba8_from(OIIO::ImageInput::open(path, &texture_read_config()), path);
}

Result<Rgba8Image> decode_rgba8_oiio(const unsigned char* data, std::size_t size,
                                     const std::string& name_hint) {
    OIIO::Filesystem::IOMemReader reader(data, size);
    // With a config, OIIO 2.4 reads the proxy from it (the separate argument is then ignored).
    OIIO::ImageSpec config = texture_read_config();
    OIIO::Filesystem::IOProxy* proxy = &reader;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    return read_rgba8_from(OIIO::ImageInput::open(name_hint, &config, &reader), name_hint);
}

constexpr OiioImages kTable{kOiioImagesAbi,  write_exr_oiio,  write_rgb8_oiio,  encode_png_oiio,
                            read_image_oiio, read_rgba8_oiio, decode_rgba8_oiio};

}  // namespace
}  // namespace pathfarm

extern "C" __attribute__((visibility("default"))) const pathfarm::OiioImages*
pathfarm_oiio_images() {
    return &pathfarm::kTable;
}
