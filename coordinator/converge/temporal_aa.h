// Temporal anti-aliasing of the denoised frames (SVGF's last step, after Karis 2014): the last
// output, carried to this frame by each pixel's motion (TemporalAccumulator::sources()), is
// clamped to the new output's 3x3 neighbourhood (per channel, its box of colours), read
// bilinearly, and blended with it by `alpha`. Under a moving camera the converging history is
// clamped and floored (a tenth of each frame is new), so the filtered frames still flicker and
// edges show one surface or the other at a sample a frame; this averages both, and the clamp
// cuts a history the neighbourhood no longer holds (a disocclusion, a switched light).
// Only on still surfaces: on and beside moving or deforming instances sources() has no motion
// and the output stays as filtered. There the surface's light changes as it moves, so a second
// lagging history adds error, and at a moving silhouette the box admits the object's colour
// into the background it left: a halo that on the Cesium Man path made the denoised error 3.4x
// what it was (denoise_bench; relative MSE weighs light on a black pixel heavily).
// Unlike the converging history it feeds back its own output: it is a display filter, and the
// accumulated light (converging) stays unbiased.
#pragma once

#include <vector>

#include "common/film/film.h"
#include "common/math/types.h"

namespace pathfarm::coord {

class TemporalAntialias {
public:
    explicit TemporalAntialias(float alpha) : alpha_(alpha) {}

    // Blends `image` in place with the last output. `sources`: per pixel, where its surface was
    // in the last frame's pixel coordinates, or negative where it was not on screen. The first
    // frame, a size change or sources of another size leave `image` as it is.
    void apply(FloatImage& image, const std::vector<Vec2>& sources);
    void reset() { history_ = FloatImage(); }
    // The last image apply() left (equal to it; empty before the first or after reset()).
    const FloatImage& history() const { return history_; }

private:
    float alpha_;
    FloatImage history_;
    FloatImage next_;                       // the history being written, swapped in at the end
    std::vector<float> row_min_, row_max_;  // each float's min and max over x-1..x+1
    std::vector<float> carried_;            // the history where each pixel's surface was
};

}  // namespace pathfarm::coord
