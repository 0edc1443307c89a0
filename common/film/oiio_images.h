// The image codecs that need OpenImageIO, kept in a module of their own (libpathfarm_oiio.so)
// that image_io.cpp loads on first use. Debian's OpenImageIO links some 260 shared libraries;
// resolving them cost every process that linked it about 0.2 s at start (78 % of it in the
// dynamic loader's symbol lookups), whether or not it ever touched an image: every test, every
// pathfarm-render --help. Now only the processes that read or write an EXR, PNG or texture
// pay, and only when they do.
//
// Both sides are built together by the same compiler from the same headers, so the table
// passes C++ types (std::string, Result) across; kOiioImagesAbi guards against a stale module.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/film/image_io.h"

namespace pathfarm {

inline constexpr int kOiioImagesAbi = 1;

struct OiioImages {
    int abi;
    Status (*write_exr)(const std::string& path, const FloatImage& image);  // float, zip
    Status (*write_rgb8)(const std::string& path, int width, int height,
                         const std::vector<uint8_t>& rgb);
    Result<std::vector<uint8_t>> (*encode_png)(int width, int height,
                                               const std::vector<uint8_t>& rgb);
    Result<FloatImage> (*read_image)(const std::string& path);  // not PFM
    Result<Rgba8Image> (*read_rgba8)(const std::string& path);
    Result<Rgba8Image> (*decode_rgba8)(const unsigned char* data, std::size_t size,
                                       const std::string& name_hint);
};

// The module's one exported symbol.
inline constexpr const char* kOiioImagesSymbol = "pathfarm_oiio_images";

// Loads the module at `path` and returns its table, or an error naming the path and what went
// wrong (missing, not a module, another build's table). Each call loads afresh (tests).
Result<const OiioImages*> load_oiio_images(const std::string& path);

// The table for this process, loaded once: from $PATHFARM_OIIO_MODULE if set, else beside the
// executable (libpathfarm_oiio.so, or ../lib/pathfarm/libpathfarm_oiio.so as deploy/
// installs it), else where the build put it. The error lists every place tried.
Result<const OiioImages*> oiio_images();

}  // namespace pathfarm
