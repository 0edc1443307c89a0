// A 3x3 dilation of a byte mask is a row pass then a column pass; both converge masks (the
// denoiser's pixels near a sharp one, converging's pixels near a moving object) share the row's.
#pragma once

#include <cstdint>

namespace pathfarm::coord {

// out[x] = in[x - 1] | in[x] | in[x + 1] over a row of w bytes, the ends replicated. The
// interior loop has no clamps, so it vectorises.
inline void dilate_row(const uint8_t* in, uint8_t* out, int w) {
    if (w == 1) {
        out[0] = in[0];
        return;
    }
    out[0] = in[0] | in[1];
    for (int x = 1; x + 1 < w; ++x)
        out[x] = in[x - 1] | in[x] | in[x + 1];
    out[w - 1] = in[w - 2] | in[w - 1];
}

}  // namespace pathfarm::coord
