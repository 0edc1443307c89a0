// Image files through OpenImageIO (PFM and JPEG textures without it), which stays behind this
// small API (STYLE.md §2.5).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/film/film.h"

namespace pathfarm {

// Writes by extension: .exr (32-bit float, zip) and .pfm hold linear radiance; .png and .jpg
// are tonemapped sRGB (tonemap.h) with the given exposure.
Status write_image(const std::string& path, const FloatImage& image, float exposure = 1.0f);
// Whether write_image can write this path's format here: a known extension, and for EXR, PNG
// and JPEG the OpenImageIO module loaded. Lets a tool fail before a long render, not after.
Status check_image_format(const std::string& path);
// Writes already-encoded 8-bit RGB bytes (for contact sheets and previews).
Status write_rgb8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

// PNG bytes of 8-bit RGB pixels, encoded in memory (frames streamed to clients).
Result<std::vector<uint8_t>> encode_png(int width, int height, const std::vector<uint8_t>& rgb);

// Reads any format OIIO knows into linear float RGB (8-bit sRGB files are decoded).
Result<FloatImage> read_image(const std::string& path);

// An 8-bit RGBA image decoded from a file or from memory (textures).
struct Rgba8Image {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;
    // Float images (EXR, HDR) are scaled from [0, 1]; NaN values become 0 and infinities clamp
    // (to 0 or 255). How many values that was, for the loader's warning.
    std::size_t nonfinite_values = 0;
};
Result<Rgba8Image> read_rgba8(const std::string& path);
// name_hint carries the extension OIIO uses to pick a decoder (e.g. "texture.png").
Result<Rgba8Image> decode_rgba8(const unsigned char* data, std::size_t size,
                                const std::string& name_hint);

}  // namespace pathfarm
