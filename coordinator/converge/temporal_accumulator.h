// Converging (Brigade §4.5) with reprojection: C = (1 - f) H + f C_new per pixel, where H is
// the previous output carried to this frame by the camera's (and each instance's) motion.
// A pixel whose surface stayed still keeps a true running mean (f = 1/k for its k-th frame,
// error falls as 1/sqrt(k); a frame that gave the pixel s times the frame's spp counts as s
// frames: f = s / k, k counting such frames); history of a moving pixel is clamped to the new
// frame's neighbourhood and f is floored so moving objects do not smear; history whose surface is
// not the one seen now (disocclusion, off-screen, another instance, a depth jump) is dropped.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <utility>

#include "common/film/film.h"
#include "coordinator/converge/gbuffer.h"
#include "coordinator/converge/neighbourhood.h"

namespace pathfarm::coord {

// A deformed instance's mesh as it is in one frame: where its pixels were is the same
// barycentric combination of a triangle's vertices one frame earlier (motion vectors).
struct SurfaceVertices {
    std::vector<Vec3> positions;    // object space
    std::vector<uint32_t> indices;  // three per triangle
};
using SurfaceMap = std::map<uint32_t, std::shared_ptr<const SurfaceVertices>>;

// What the accumulator must know about a frame besides its pixels.
struct FrameView {
    Camera camera;
    GBuffer gbuffer;                     // at the display resolution
    std::map<uint32_t, Mat4> instances;  // instance id -> object-to-world this frame
    std::set<uint32_t> deformed;         // instances whose vertices changed this frame
    // Their vertices after the change, by instance id. A deformed instance without them, or
    // whose vertices the accumulator has not seen before, keeps no history.
    SurfaceMap surfaces;
    // Lighting, materials or the environment changed: no history is valid (a cut).
    bool cut = false;
    // Samples each pixel took this frame over the frame's spp (more where workload scaling
    // gave extra samples: coordinator/pacing/extra_samples.h), at the display resolution;
    // empty: 1 everywhere. The running mean weighs each frame by them.
    std::vector<float> sample_weights;
};

struct ConvergeOptions {
    float object_floor = 0.3f;    // least f on pixels of moving instances and beside them
    float deformed_floor = 0.4f;  // least f on pixels of instances deforming this frame
    float camera_floor = 0.1f;    // least f on still surfaces seen by a moving camera
    // Least f on still glossy surfaces (GBuffer::glossy) seen by a moving camera: their
    // reflections move over them, so history reprojected with the surface lags. Converging
    // keeps camera_floor (pathfarm-denoise-bench game, 0.1 / 0.2 / 0.3: converging's relative
    // MSE 1.553 / 1.574 / 1.609); the denoiser's accumulator uses DenoiseOptions::glossy_floor.
    float glossy_floor = 0.1f;
    float clamp_sigmas = 1.5f;      // history clamp: neighbourhood mean +- this many deviations
    float depth_tolerance = 0.03f;  // relative distance mismatch that rejects history
};

// TemporalAccumulator::sources() of a pixel whose surface was off screen (or not known).
inline constexpr float kNoSource = -1.0f;

struct ConvergeStats {
    double mean_f = 1.0;       // mean blend factor over the frame's pixels
    double kept = 0.0;         // fraction of pixels that kept history
    double mean_frames = 1.0;  // mean history length (frames) after this one
};

class TemporalAccumulator {
public:
    explicit TemporalAccumulator(ConvergeOptions options = {}) : o_(options) {}

    // Blends `image` (this frame's new samples, display resolution) with the history in place.
    ConvergeStats blend(FloatImage& image, FrameView view);
    void reset();  // a cut: the next frame starts from its own samples only
    // Frames of history per pixel, in frames of the frame's spp (1: this frame's samples alone,
    // more when extra samples gave it more).
    const std::vector<float>& history_frames() const { return frames_; }
    // Per pixel, the running means of the blended image's luminance and of its square (SVGF's
    // first two moments), blended with the same factors: their difference is the variance of
    // the frames' luminance where the history is long enough.
    const std::vector<Vec2>& moments() const { return moments_; }
    // Per pixel of the last blended frame, where its surface was in the frame before, in that
    // frame's pixel coordinates (x + 0.5 at a pixel's centre), whether or not its history was
    // kept (an edge's pixel may keep none, but its surface was there): the motion vectors of
    // the denoiser's temporal anti-aliasing (temporal_aa.h). kNoSource where off screen or
    // unknown, and on and beside moving or deforming instances, which it leaves alone.
    const std::vector<Vec2>& sources() const { return sources_; }
    float min_history_frames() const;                      // 0 before the first frame
    const FloatImage& output() const { return history_; }  // the last blended image
    // The last blended frame's G-buffer (kept for the next frame's reprojection); null before
    // the first frame.
    const GBuffer* gbuffer() const { return previous_ ? &previous_->gbuffer : nullptr; }
    // The G-buffer of the frame before the last, no longer needed, for the next frame's to be
    // written into (gbuffer_from_first_hits: its planes are already sized); empty if none.
    GBuffer take_spare_gbuffer() { return std::exchange(spare_gbuffer_, GBuffer{}); }

private:
    void start_over(const FloatImage& image, FrameView view);  // this frame's samples alone
    void size_outputs(int w, int h);                           // the blend's outputs at w x h
    void keep(FrameView view);              // the blend's outputs become the history
    void replace_previous(FrameView view);  // keeping the old one's G-buffer as the spare
    void remember_surfaces(const FrameView& view);

    ConvergeOptions o_;
    FloatImage history_;
    std::vector<float> frames_;
    std::vector<Vec2> moments_;
    std::vector<Vec2> sources_;
    std::optional<FrameView> previous_;
    GBuffer spare_gbuffer_;  // previous_'s when a newer view replaced it
    // Each deformed instance's vertices as last seen: its vertices in the previous frame, since
    // every change of them comes with the frame's view.
    SurfaceMap last_surfaces_;
    FloatImage next_history_;  // the blend's outputs before they become the history
    std::vector<float> next_frames_;
    std::vector<Vec2> next_moments_;
    NeighbourhoodStats neighbourhood_;  // of the new frame, for the history clamp
    std::vector<uint8_t> near_now_, near_prev_, near_tmp_;  // near a moving instance, per pixel
};

}  // namespace pathfarm::coord
