// Spatio-temporal reconstruction after SVGF (Schied et al. 2017): the frame's light is divided
// by the base colour over each pixel's footprint (from the first hits), accumulated over frames
// with the converging reprojection (TemporalAccumulator, with the first two moments of its
// luminance), given a per-pixel variance (temporal where the history is long, spatial where it is
// short), filtered by the edge-avoiding à-trous wavelet (atrous.h), multiplied by the base
// colour again and, over frames, given the mix of both sides on the far side of silhouettes
// where history is short (edge_coverage.h) and blended with its last output where surfaces
// stood still (temporal anti-aliasing, temporal_aa.h).
//
// What stays sharp, per pixel: a pixel the tracers flagged sharp (an emitter seen directly,
// rough glass, a mirror or clear glass showing no surface beyond: FirstHit::kSharp), the
// pixels next to one (their other samples may have seen it) and the sky keep their own
// accumulated light and are no neighbour's tap: their light is not a base colour times a
// smooth irradiance. Where a mirror or clear glass shows a surface, the first hit is that
// surface (FirstHit::kReplaced) and its light is filtered like any other.
#pragma once

#include "coordinator/converge/atrous.h"
#include "coordinator/converge/edge_coverage.h"
#include "coordinator/converge/temporal_aa.h"
#include "coordinator/converge/temporal_accumulator.h"

namespace pathfarm::coord {

struct DenoiseOptions {
    AtrousOptions atrous;
    int variance_frames = 4;  // shorter history: the variance is estimated spatially
    // Demodulation divides by max(base colour, this): a dark channel's light divided by a
    // small base colour is mostly its samples' error (denoise_bench: 0.1 against 0.02 cut the
    // game path's relative MSE 6 %, the others' by 1 % or less).
    float albedo_floor = 0.1f;
    // The temporal anti-aliasing's blend factor (temporal_aa.h) on the temporal path; 0: off.
    // denoise_bench, relative MSE over converging's at 0 / 0.15 / 0.3 / 0.5: Sponza walk 0.201 /
    // 0.138 / 0.137 / 0.146, game path 0.128 / 0.121 / 0.103 / 0.101.
    float taa_alpha = 0.3f;
    // The least blend factor of its accumulator on glossy surfaces under a moving camera
    // (ConvergeOptions::glossy_floor). pathfarm-denoise-bench game, relative MSE at 0.1 / 0.2 /
    // 0.3 / 0.5: 0.1144 / 0.1071 / 0.1056 / 0.1042, SSIM 0.5884 / 0.5899 / 0.5893 / 0.5883; the
    // Sponza walk and Cesium Man show no glossy surface and are unchanged.
    float glossy_floor = 0.3f;
    // The far side of silhouettes, where history is short (edge_coverage.h), on the temporal
    // path.
    EdgeCoverageOptions edges;
};

inline ConvergeOptions with_glossy_floor(ConvergeOptions o, float glossy_floor) {
    o.glossy_floor = glossy_floor;
    return o;
}

class Denoiser {
public:
    explicit Denoiser(DenoiseOptions options = {}, ConvergeOptions converge = {})
        : o_(options),
          accumulator_(with_glossy_floor(converge, options.glossy_floor)),
          atrous_(options.atrous),
          taa_(options.taa_alpha),
          edges_(options.edges) {}

    // Denoises `image` (the frame at the G-buffer's resolution) in place. `temporal`: with
    // the history of earlier frames (the farm converging); otherwise this frame alone. Returns
    // the temporal accumulation's statistics ({1, 0, 1} for a frame alone).
    ConvergeStats filter(FloatImage& image, FrameView view, bool temporal);
    void reset() {
        if (output_is_taa_) output_ = taa_.history();  // the last output stays shown
        output_is_taa_ = false;
        accumulator_.reset();
        taa_.reset();
    }
    float min_history_frames() const { return accumulator_.min_history_frames(); }
    const std::vector<float>& history_frames() const { return accumulator_.history_frames(); }
    GBuffer take_spare_gbuffer() { return accumulator_.take_spare_gbuffer(); }  // (accumulator)
    // The last denoised image.
    const FloatImage& output() const { return output_is_taa_ ? taa_.history() : output_; }

private:
    void prepare(const GBuffer& g, const Camera& camera);
    void estimate_variance(const std::vector<Vec2>& moments, const std::vector<float>* frames,
                           int w, int h);

    DenoiseOptions o_;
    TemporalAccumulator accumulator_;
    AtrousFilter atrous_;
    TemporalAntialias taa_;
    EdgeCoverage edges_;
    // The last output where the anti-aliasing step does not keep it (a copy of a frame less
    // on the temporal path).
    FloatImage output_;
    bool output_is_taa_ = false;
    // Per-frame planes, kept to spare the allocations.
    std::vector<uint8_t> filter_mask_, near_sharp_;
    std::vector<Rgb> albedo_, albedo_tmp_;
    std::vector<Vec2> moments_;
    std::vector<float> variance_, m1_, m2_, tmp_, tmp2_, blur1_, blur2_;
};

// One frame alone (pathfarm-render --denoise): the spatial filter with a spatial variance.
// The G-buffer is taken by value: a caller done with it moves it in (a copy is 60 bytes a
// pixel, every page of it a fault in a fresh process).
void denoise_frame(FloatImage& image, GBuffer gbuffer, const Camera& camera,
                   const DenoiseOptions& options = {});

}  // namespace pathfarm::coord
