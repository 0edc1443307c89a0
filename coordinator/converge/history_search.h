// Which pixel of the last frame holds a reprojected point's history (TemporalAccumulator).
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>

#include "coordinator/converge/gbuffer.h"

namespace pathfarm::coord {

// Whether the last frame's pixel k saw instance `inst` at distance `expected`.
inline bool same_surface(const GBuffer& prev, std::size_t k, uint32_t inst, float expected,
                         float depth_tolerance) {
    return prev.instance[k] == inst &&
           (inst == GBuffer::kNoInstance ||
            std::abs(prev.distance[k] - expected) <= depth_tolerance * expected);
}

// At an edge the pixel (hx, hy) the point (px, py) falls in may show the other side while one
// beside it, within a pixel of the point, shows this surface (SVGF searches the footprint too):
// without this, every pixel along an edge under a moving camera started over each frame.
// Nearest first; not a pixel `near_prev` marks (beside a moving object last frame: its light
// may hold the object's edge, a ghost outline), so what a moving object uncovers still starts
// over (the caller passes none for a moving object's own pixels). On success (hx, hy) is the
// pixel found.
inline bool search_footprint(const GBuffer& prev, const uint8_t* near_prev, uint32_t inst,
                             float expected, float depth_tolerance, float px, float py, int& hx,
                             int& hy) {
    const float fx = px - float(hx) - 0.5f, fy = py - float(hy) - 0.5f;
    const int ox = fx < 0.0f ? -1 : 1, oy = fy < 0.0f ? -1 : 1;
    const bool x_first = std::abs(fx) >= std::abs(fy);
    const std::pair<int, int> order[3] = {x_first ? std::pair{ox, 0} : std::pair{0, oy},
                                          x_first ? std::pair{0, oy} : std::pair{ox, 0},
                                          {ox, oy}};
    for (const auto& [dx, dy] : order) {
        const int nx = hx + dx, ny = hy + dy;
        if (nx < 0 || ny < 0 || nx >= prev.width || ny >= prev.height) continue;
        const std::size_t k = std::size_t(ny) * prev.width + nx;
        if ((near_prev && near_prev[k]) || !same_surface(prev, k, inst, expected, depth_tolerance))
            continue;
        hx = nx, hy = ny;
        return true;
    }
    return false;
}

}  // namespace pathfarm::coord
