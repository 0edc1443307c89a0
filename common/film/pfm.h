// Portable Float Map: Debian's OpenImageIO has no PFM writer, and the format is four header
// lines and raw floats, so pathfarm reads and writes it itself (RGB, little endian).
#pragma once

#include <string>

#include "common/base/result.h"
#include "common/film/film.h"

namespace pathfarm {

Status write_pfm(const std::string& path, const FloatImage& image);
Result<FloatImage> read_pfm(const std::string& path);

}  // namespace pathfarm
