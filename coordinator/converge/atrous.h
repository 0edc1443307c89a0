// The edge-avoiding à-trous wavelet filter of SVGF (Schied et al. 2017, after Dammertz et al.
// 2010): levels of a B-spline kernel (3x3, or SVGF's 5x5) with taps 2^level pixels apart, each
// tap weighted by how far it lies off the centre pixel's tangent plane, how its normal turns
// away (max(0, n_p . n_q)^128, SVGF's) and how its luminance differs relative to the centre's
// standard deviation. The variance is filtered alongside (with squared weights) so later
// levels stop at what is left of the noise.
#pragma once

#include <vector>

#include "common/base/memory.h"
#include "common/film/film.h"
#include "common/scene/camera.h"
#include "coordinator/converge/gbuffer.h"

namespace pathfarm::coord {

struct AtrousOptions {
    int levels = 5;
    int radius = 1;  // 1: 3x3 taps, 2: SVGF's 5x5 (docs/denoise.md)
    // Luminance edge: this many standard deviations (SVGF: 4). 8 where the variance is the
    // frames' own (temporal), 4 where it is estimated from one frame's neighbourhood, which
    // counts the picture's own detail as noise too (docs/denoise.md: both measured).
    float sigma_luminance = 8.0f;
    float sigma_luminance_spatial = 4.0f;
    float sigma_plane = 1.0f;  // depth edge: distance off the tangent plane, in footprints
};

// The instruction sets the wavelet's row pass is built for, in order; the best one the CPU
// runs is used.
enum class AtrousIsa { kBaseline, kX86_64_V3, kX86_64_V4 };
// For tests and benchmarks: run the rows with `isa` from now on (process-wide). False, and
// nothing changed, if the CPU lacks it.
bool use_atrous_isa(AtrousIsa isa);
AtrousIsa atrous_isa();

// The filter with its planes, kept from frame to frame (no allocation once sized). Planes are
// padded by the widest tap offset on every side with pixels that are no one's tap, so the
// inner loops need no bounds checks and vectorise.
class AtrousFilter {
public:
    explicit AtrousFilter(AtrousOptions options = {}) : o_(options) {}

    // The frame's edges: normal, camera-relative position and footprint of each pixel with
    // `filter[i]` set; the others keep their values and are no pixel's taps.
    void set_guide(const GBuffer& g, const Camera& camera, const std::vector<uint8_t>& filter);
    // Filters `image` (demodulated light, the guide's size) in place; `variance` is each
    // pixel's luminance variance, `spatial` whether it was estimated from one frame alone.
    // Each pixel is multiplied by `modulate`'s as it is written back (the denoiser's base
    // colour).
    void filter(FloatImage& image, const std::vector<float>& variance, bool spatial,
                const std::vector<Rgb>& modulate);
    const AtrousOptions& options() const { return o_; }

private:
    void allocate(int width, int height, int pad);
    // One row of the guide; fy: the row's film y at unit depth.
    void guide_row(const GBuffer& g, const Mat3& m, const std::vector<uint8_t>& filter, int y,
                   float fy, float inv_sigma_pitch);
    void level(int step, int from, float sigma_l);
    void replicate_edges(float* plane) const;

    AtrousOptions o_;
    int width_ = 0, height_ = 0, pad_ = 0, stride_ = 0;
    float pitch_ = 0.0f;  // a pixel's width on the film at unit depth
    // Guide (padded, camera space): normal, depth along the view axis, n . film point, n .
    // point, inverse plane tolerance (0: not filtered).
    float *nx_ = nullptr, *ny_ = nullptr, *nz_ = nullptr, *z_ = nullptr, *slope_ = nullptr,
          *offset_ = nullptr, *inv_plane_ = nullptr;
    std::vector<float> film_x_;  // per column: the pixel centre's film x at unit depth
    // Colour and variance, in and out of a level (padded).
    float *rgb_[2][3] = {}, *var_[2] = {};
    // The 15 planes above, in one allocation, each starting 64 bytes further into a 4 KiB page
    // than the last: a tap reads the same pixel of every plane, and planes at one page offset
    // (separate allocations, each page-aligned) compete for the same cache sets. On huge
    // pages where the system allows (HugePageBuffer).
    HugePageBuffer planes_;
};

}  // namespace pathfarm::coord
