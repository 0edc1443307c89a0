// Display transform: exposure, the ACES filmic fit (Narkowicz 2015), then sRGB encoding.
// Only for display; films stay linear (DESIGN.md, "Conventions").
#pragma once

#include <cstdint>
#include <vector>

#include "common/film/film.h"

namespace pathfarm {

// 8-bit sRGB RGB bytes, row 0 at the top.
std::vector<uint8_t> tonemap_to_srgb8(const FloatImage& image, float exposure = 1.0f);
// Rows [y0, y1) of that into `out`, the whole image's bytes (a caller's threads each take some
// rows: coordinator/frame/parallel_image.h).
void tonemap_rows_to_srgb8(const FloatImage& image, float exposure, int y0, int y1, uint8_t* out);

// One channel of the above: a linear value (non-finite counts as 0) to its 8-bit code.
uint8_t tonemap_channel(float linear, float exposure = 1.0f);
// The 8-bit code of a display value in [0, 1] (the ACES fit's output): srgb8_code finds it
// from a table of thresholds, srgb8_reference by its definition, round(255 * sRGB(display)).
uint8_t srgb8_code(float display);
int srgb8_reference(float display);

}  // namespace pathfarm
