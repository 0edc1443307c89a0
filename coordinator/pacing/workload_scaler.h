// Dynamic workload scaling (Brigade §4.7): holds a target frame rate by moving down (or back
// up) a ladder of quality levels, cheapest knob first: samples per pixel (between one spp and
// the next, a share of the pixels takes one more: extra_samples.h), then the Russian-roulette
// survival probability, then the render resolution (upscaled for display). It never
// goes below the configured floor; when even the floor is too slow it says so (at_floor()).
//
// The controller predicts a level's frame time as fixed + k * work(level), where work is the
// relative cost (spp x pixels x a path-length factor), k is learned from the tracers' render
// time and `fixed` from the rest of the frame (commit, replica and backend updates, tile
// transfer), which no quality level changes: scaling all of the frame time with the work
// left a third of the tracers' time unused. A capacity drop (a tracer leaves) shows as a
// jump in k and is acted on at once; rises in quality need the prediction to fit with a
// margin, and climb one level a frame or several within 1.1x in work, so it does not
// oscillate.
#pragma once

#include <vector>

namespace pathfarm::coord {

struct QualityLevel {
    int spp = 1;
    float extra = 0.0f;       // samples beyond spp per pixel on average, in [0, 1)
    float rr_scale = 1.0f;    // Russian-roulette survival scale (1: unscaled)
    float resolution = 1.0f;  // render size over display size, per axis
};

struct ScalerOptions {
    double target_fps = 30.0;
    int max_spp = 1;
    float min_rr_scale = 0.5f;
    float min_resolution = 0.5f;
    // Aim frame time at this fraction of the frame interval: what is left is the loop's own
    // prepare and send (the display runs beside the next frame: session/frame_display.h).
    double headroom = 0.9;
    double rise_margin = 0.96;  // a better level must be predicted within this much of that
};

class WorkloadScaler {
public:
    explicit WorkloadScaler(const ScalerOptions& options);

    const QualityLevel& level() const { return ladder_[index_]; }
    // Reports how long the frame rendered at level() took (assignment to last tile) and how
    // much of that the slowest tracer spent rendering (<= 0: unknown, all of it scales), and
    // picks the level of the next frame.
    void observe(double frame_ms, double render_ms = 0.0);
    double predict_ms(const QualityLevel& level) const;
    // The lowest level is in use and still slower than the target.
    bool at_floor() const { return at_floor_; }
    const std::vector<QualityLevel>& ladder() const { return ladder_; }
    static double work(const QualityLevel& level);  // relative cost, 1 at 1 spp full quality

private:
    static constexpr double kMaxRise = 1.1;  // work(next level) / work(level) at most
    static constexpr double kStep = 1.03;    // the ladder's steps in work, where they are fine
    ScalerOptions o_;
    std::vector<QualityLevel> ladder_;  // best first
    std::size_t index_ = 0;
    double ms_per_work_ = 0.0;  // learned k; 0 until the first frame
    double fixed_ms_ = 0.0;     // learned per-frame time that does not scale with the work
    bool at_floor_ = false;
};

}  // namespace pathfarm::coord
