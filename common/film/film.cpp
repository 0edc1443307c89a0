// Whole-image queries on FloatImage.
#include "common/film/film.h"

#include <cmath>

namespace pathfarm {

std::size_t count_nonfinite(const FloatImage& image) {
    std::size_t n = 0;
    for (float v : image.rgb)
        n += std::isfinite(v) ? 0 : 1;
    return n;
}

}  // namespace pathfarm
