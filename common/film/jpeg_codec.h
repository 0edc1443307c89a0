// JPEG frames for clients through libturbojpeg: the default codec of the frame stream, since a
// 320x180 frame is ~10 KB as JPEG against ~100 KB as PNG and encodes in well under a
// millisecond. Lossy; PNG and zstd floats remain for clients that need exact pixels.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/base/result.h"

namespace pathfarm {

// rgb: width*height*3 sRGB bytes, row 0 at the top. quality in [1, 100].
Result<std::string> encode_jpeg(int width, int height, const std::vector<uint8_t>& rgb,
                                int quality);

struct Rgb8Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;  // width*height*3, row 0 at the top
};

Result<Rgb8Image> decode_jpeg(const std::string& bytes);

}  // namespace pathfarm
