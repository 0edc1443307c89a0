// Where a frame spends samples beyond spp (FrameSpec::extra_samples). Workload scaling gives a
// frame a budget between one spp and the next (QualityLevel::extra) when the tracers would
// otherwise sit idle part of each frame; this plan decides which pixels take it.
//
// Pixels with little history come first: a pixel whose history was just rejected (a
// disocclusion, a moving object's silhouette, a deforming figure) shows this frame's samples
// almost alone, while one with a long history gains little from another sample. The history
// is the converging accumulator's as the last shown frame left it, spread to the pixels within
// kReach of each pixel (the map is used one or two frames later, and moving edges move). Each
// young pixel wants enough samples that its history plus them makes kWantedFrames; the budget
// goes round by round, one more sample to every pixel still wanting one, those that want most
// first (ties in dither order), so all young pixels get their second sample before any gets
// its third. What the young pixels do not take is spread over the whole frame by an ordered
// dither that moves every frame.
//
// Choosing a pixel's sample count from earlier frames does not bias it: the count is fixed
// before any of this frame's random numbers are drawn.
#pragma once

#include <cstdint>
#include <vector>

namespace pathfarm::coord {

struct ExtraSamplePlan {
    static constexpr int kReach = 2;           // pixels a young pixel's need spreads to
    static constexpr float kWantedFrames = 4;  // history plus extra samples a pixel should have
    static constexpr int kMaxTargeted = 3;     // extra samples one young pixel may take
};

// The extra samples of each pixel of a width x height frame, row-major, summing to at most
// round(budget * width * height) (budget: extra samples per pixel on average, in [0, 1]).
// `history_frames` is the accumulator's history length per pixel at this size (empty when
// there is none, or it was at another size: then the dither alone). `frame` moves the dither.
std::vector<uint8_t> plan_extra_samples(const std::vector<float>& history_frames, int width,
                                        int height, double budget, uint64_t frame);

// Each pixel's samples over `spp` under the plan `extra` (FrameView::sample_weights).
std::vector<float> sample_weights(const std::vector<uint8_t>& extra, int spp);

}  // namespace pathfarm::coord
