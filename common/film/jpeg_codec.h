// JPEG through libturbojpeg: frames for clients (the default codec of the frame stream, since a
// 320x180 frame is ~10 KB as JPEG against ~100 KB as PNG and encodes in well under a
// millisecond; lossy, so PNG and zstd floats remain for clients that need exact pixels), and
// JPEG textures without loading the OpenImageIO module (image_io.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/film/image_io.h"

namespace pathfarm {

// rgb: width*height*3 sRGB bytes, row 0 at the top. quality in [1, 100].
Result<std::string> encode_jpeg(int width, int height, const std::vector<uint8_t>& rgb,
                                int quality);

struct Rgb8Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;  // width*height*3, row 0 at the top
};

Result<Rgb8Image> decode_jpeg(const std::string& bytes);

// Whether bytes start as a JPEG file does (its SOI marker and the next marker's first byte).
bool looks_like_jpeg(const unsigned char* data, std::size_t size);

// A JPEG texture as RGBA (alpha 255), decoded as OpenImageIO's JPEG reader decodes it: the
// same libjpeg-turbo with its defaults (the accurate integer DCT, smooth chroma upsampling), so
// the same bytes (JpegTexture.* compares them). Nothing where TurboJPEG cannot decode it
// cleanly (CMYK, damage it only warns about): such files go to OpenImageIO, as all did before.
std::optional<Rgba8Image> decode_jpeg_rgba8(const unsigned char* data, std::size_t size);

}  // namespace pathfarm
