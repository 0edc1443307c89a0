// The quality ladder and its controller.
#include "coordinator/pacing/workload_scaler.h"

#include <algorithm>
#include <cmath>

namespace pathfarm::coord {

WorkloadScaler::WorkloadScaler(const ScalerOptions& options) : o_(options) {
    // Steps of at most about 1.5x in work: a coarser ladder leaves the budget unused (with
    // resolution steps of 10 % the demo's frames settled at 76 ms of a 90 ms budget, the next
    // step up predicted at 94).
    // From 4 spp down, steps of one spp are split by extra samples into steps of about 1.03x:
    // with whole samples alone a farm that could not afford 2 spp sat at 1 with its tracers
    // idle 30 % of each frame (the demo at 320x180); with steps of 1.1x, at 77 % (the frame
    // settles anywhere below the rise margin by up to a step).
    for (int spp = std::max(1, o_.max_spp); spp >= 1; spp = spp > 4 ? (spp * 2) / 3 : spp - 1) {
        ladder_.push_back({spp, 0.0f, 1.0f, 1.0f});
        if (spp == 1 || spp > 4) continue;
        const int steps = int(std::ceil(std::log(double(spp) / (spp - 1)) / std::log(kStep)));
        for (int k = steps - 1; k >= 1; --k)
            ladder_.push_back({spp - 1, float(k) / float(steps), 1.0f, 1.0f});
    }
    for (float rr : {0.75f, 0.5f, 0.35f})
        if (rr >= o_.min_rr_scale) ladder_.push_back({1, 0.0f, rr, 1.0f});
    // Resolution steps of about 1.03x in work too (1.5 % per axis), down to the floor: with
    // steps of 5 % (1.1x) the demo, which sits below 1 spp, settled anywhere down to a step
    // below the rise margin, its tracers rendering 77 % of the time.
    const float rr = ladder_.back().rr_scale;
    const double per_axis = 1.0 / std::sqrt(kStep);
    for (double res = per_axis; res > double(o_.min_resolution) * 1.001; res *= per_axis)
        ladder_.push_back({1, 0.0f, rr, float(res)});
    if (o_.min_resolution < 1.0f) ladder_.push_back({1, 0.0f, rr, o_.min_resolution});
}

double WorkloadScaler::work(const QualityLevel& l) {
    // Frame time under scaled roulette, measured on builtin:default 320x180 at 1 spp
    // (bench/realtime_bench.py, median frame 74 ms at scale 1, 66 ms at 0.5): the primary
    // ray, the first bounces (before roulette starts) and shading keep most of the cost.
    const double path = 0.78 + 0.22 * double(l.rr_scale);
    return (double(l.spp) + double(l.extra)) * double(l.resolution) * double(l.resolution) * path;
}

double WorkloadScaler::predict_ms(const QualityLevel& l) const {
    return fixed_ms_ + ms_per_work_ * work(l);
}

void WorkloadScaler::observe(double frame_ms, double render_ms) {
    if (!(frame_ms > 0.0)) return;
    const double scaling = render_ms > 0.0 ? std::min(render_ms, frame_ms) : frame_ms;
    const double k = scaling / work(level()), fixed = frame_ms - scaling;
    // Learn k and the fixed part: adopt a sudden slowdown at once, smooth everything else.
    const bool first = ms_per_work_ == 0.0;
    ms_per_work_ = first || k > 1.3 * ms_per_work_ ? k : 0.7 * ms_per_work_ + 0.3 * k;
    fixed_ms_ = first || fixed > 1.3 * fixed_ms_ + 5.0 ? fixed : 0.7 * fixed_ms_ + 0.3 * fixed;
    const double budget = o_.headroom * 1000.0 / o_.target_fps;
    std::size_t best = ladder_.size() - 1;  // the best level predicted to fit
    for (std::size_t i = 0; i < ladder_.size(); ++i)
        if (predict_ms(ladder_[i]) <= budget) {
            best = i;
            break;
        }
    if (best > index_) {
        index_ = best;  // too slow: drop as far as needed at once
    } else {
        // Room to spare: one level up, and further while the levels stay within kMaxRise of
        // this one's work, each predicted within the margin: a misjudged rise costs one slow
        // frame, not a stall.
        const double limit = kMaxRise * work(level());
        for (bool one = true; index_ > 0 && (one || work(ladder_[index_ - 1]) <= limit) &&
                              predict_ms(ladder_[index_ - 1]) <= o_.rise_margin * budget;
             one = false)
            --index_;
    }
    at_floor_ = index_ == ladder_.size() - 1 && predict_ms(level()) > budget / o_.headroom;
}

}  // namespace pathfarm::coord
