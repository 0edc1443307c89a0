// Resampling for display: frames rendered below the display resolution (workload scaling)
// are upscaled bilinearly before converging and encoding.
#pragma once

#include "common/film/film.h"

namespace pathfarm {

FloatImage resize_bilinear(const FloatImage& image, int width, int height);

}  // namespace pathfarm
