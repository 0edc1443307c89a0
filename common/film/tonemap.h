// Display transform: exposure, the ACES filmic fit (Narkowicz 2015), then sRGB encoding.
// Only for display; films stay linear (DESIGN.md, "Conventions").
#pragma once

#include <cstdint>
#include <vector>

#include "common/film/film.h"

namespace pathfarm {

// 8-bit sRGB RGB bytes, row 0 at the top.
std::vector<uint8_t> tonemap_to_srgb8(const FloatImage& image, float exposure = 1.0f);

}  // namespace pathfarm
