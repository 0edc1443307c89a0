// The far side of a silhouette, where the history is short. A pixel whose centre hit sees the
// background beside an object in front (a nearer surface across one of its four edges, or the
// sky beside any surface) has jittered samples that land anywhere in the pixel: at one sample a
// frame, with the object's edge within the pixel, some show the object. Such a sample is all
// object where the pixel holds a fraction of it (about 1/8 when the edge lies uniformly between
// the two centres), and the wavelet keeps it (it filters each side on its own, and its
// luminance edge stops at the outlier): on the Cesium Man path one such pixel was 22 % of a
// frame's relative MSE (docs/denoise.md). So where such a pixel's light is nearer in luminance
// to the object's than to its own side's (or, in its first frame, lies beyond any light its
// own side shows nearby, towards the object's), it is taken as a sample of the object and blended
// towards the mix (1 - c) B + c F, with B and F the two sides' light read from pixels nearby
// that are not on the edge (the median in luminance: a pixel beside the edge may hold such a
// sample too) and c the object's mean coverage, 1/8 per edge it lies across. The blend weight
// m / (m + k) for k frames of history lets a still view converge to its own samples as before.
//
// Only the far side: a pixel whose centre sees the object and whose sample saw the background
// often holds less of the object than its centre says (a limb a pixel wide), and pulling it
// towards the object's light made Cesium Man's error 16 % worse where this rule cuts it 12 %
// (denoise_bench; docs/denoise.md, step 6 and "The far side of silhouettes", which also has
// the measured c and m).
#pragma once

#include <cstdint>
#include <vector>

#include "common/film/film.h"

namespace pathfarm::coord {

struct EdgeCoverageOptions {
    float model_frames = 3.0f;         // m above (denoise_bench: 3 gave 0.576x, 10 0.573x); 0: off
    float coverage_per_side = 0.125f;  // c per edge (0 to 0.125: 0.572-0.574x; 0.333 0.593x)
};

class EdgeCoverage {
public:
    explicit EdgeCoverage(EdgeCoverageOptions options = {}) : o_(options) {}

    // The frame's surfaces: `surface[i]` names the surface pixel i's centre saw (an instance,
    // 0 for the sky) at `distance[i]` (+inf for the sky); `filtered[i]`: the wavelet filters
    // the pixel. A hit pixel it does not filter is sharp or beside a sharp one: it keeps its own
    // light and is no side's sample either.
    void set_surfaces(const std::vector<uint32_t>& surface, const std::vector<float>& distance,
                      const std::vector<uint8_t>& filtered, int width, int height);
    // Blends the far-side edge pixels of `image` (the frame's output, the surfaces' size) whose
    // light looks like the front surface's towards the mix; `frames[i]`: pixel i's history in
    // frames (>= 1). `surface` and `distance` as given to set_surfaces (passed again rather
    // than copied there: the denoiser hands the frame's G-buffer to the accumulator between
    // the two calls).
    void apply(FloatImage& image, const std::vector<float>& frames,
               const std::vector<uint32_t>& surface, const std::vector<float>& distance);

private:
    // The frame's surfaces as apply() is given them.
    struct Surfaces {
        const uint32_t* surface;
        const float* distance;
    };
    // behind_range: the least and largest luminance among the pixels behind's median is of.
    bool sides(const FloatImage& image, const Surfaces& s, int x, int y, Rgb& behind, Rgb& front,
               float behind_range[2]) const;
    Rgb blended(const FloatImage& image, const Surfaces& s, std::size_t i, float frames) const;

    EdgeCoverageOptions o_;
    int width_ = 0, height_ = 0;
    std::vector<uint8_t> keep_;            // hit pixels the wavelet does not filter
    std::vector<uint8_t> on_edge_;         // a 4-neighbour sees another surface
    std::vector<uint8_t> across_;          // how many 4-neighbours do
    std::vector<uint8_t> behind_;          // one of them is nearer the camera
    std::vector<uint32_t> edges_;          // far-side edge pixels not kept, in order
    std::vector<uint32_t> short_history_;  // those of them whose history leaves the mix weight
    std::vector<Rgb> blended_;             // their new values, before they are written
    std::vector<float> luminance_;         // of the image being blended, per pixel
};

}  // namespace pathfarm::coord
