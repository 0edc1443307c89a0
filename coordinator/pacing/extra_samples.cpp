// The extra-sample plan: young pixels first, round by round, then an ordered dither.
#include "coordinator/pacing/extra_samples.h"

#include <algorithm>
#include <cmath>

namespace pathfarm::coord {
namespace {

// The extra samples each pixel wants for its own history: enough to make kWantedFrames, at most
// kMaxTargeted.
std::vector<uint8_t> own_wants(const std::vector<float>& history) {
    std::vector<uint8_t> want(history.size());
    for (std::size_t i = 0; i < history.size(); ++i) {
        const float w = std::floor(ExtraSamplePlan::kWantedFrames - history[i]);
        want[i] = uint8_t(std::clamp(w, 0.0f, float(ExtraSamplePlan::kMaxTargeted)));
    }
    return want;
}

// The most any pixel within kReach wants (a separable max filter over bytes: the plan runs on
// the frame loop's critical path, so rows at a time, which the compiler vectorises).
std::vector<uint8_t> spread_wants(const std::vector<uint8_t>& want, int width, int height) {
    constexpr int r = ExtraSamplePlan::kReach;
    const auto w = std::size_t(width);
    std::vector<uint8_t> cols(want.size()), out(want.size());
    for (int y = 0; y < height; ++y) {
        uint8_t* dst = &cols[std::size_t(y) * w];
        std::copy_n(&want[std::size_t(y) * w], w, dst);
        for (int d = std::max(0, y - r); d <= std::min(height - 1, y + r); ++d) {
            const uint8_t* src = &want[std::size_t(d) * w];
            for (std::size_t x = 0; x < w; ++x)
                dst[x] = std::max(dst[x], src[x]);
        }
    }
    for (int y = 0; y < height; ++y) {
        const uint8_t* src = &cols[std::size_t(y) * w];
        uint8_t* dst = &out[std::size_t(y) * w];
        for (int x = 0; x < width; ++x) {
            uint8_t m = 0;
            for (int d = std::max(0, x - r); d <= std::min(width - 1, x + r); ++d)
                m = std::max(m, src[d]);
            dst[x] = m;
        }
    }
    return out;
}

// The rank (0-63) of pixel (x, y) in an 8x8 Bayer matrix: any threshold picks pixels spread
// evenly over every 8x8 block. The bits of x ^ y and y, interleaved and reversed.
int bayer_rank(int x, int y) {
    int rank = 0;
    for (int bit = 0; bit < 3; ++bit)
        rank = (rank << 2) | ((((x ^ y) >> bit) & 1) << 1) | ((y >> bit) & 1);
    return rank;
}

// The dither's rank of each pixel this frame: the matrix shifted by a step that visits every
// offset, so over 64 frames every pixel takes its turn.
std::vector<uint8_t> dither_ranks(int width, int height, uint64_t frame) {
    const int ox = int((frame * 3) % 8), oy = int((frame * 5 + frame / 8) % 8);
    uint8_t shifted[8][8];
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            shifted[y][x] = uint8_t(bayer_rank((x + ox) & 7, (y + oy) & 7));
    std::vector<uint8_t> ranks(std::size_t(width) * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            ranks[std::size_t(y) * width + x] = shifted[y & 7][x & 7];
    return ranks;
}

// Gives young pixels what they want, round by round, those that want most first and, among
// them, in dither order (so an even cut of a uniformly young frame is spread over it). The
// order is a counting sort by (want, rank): a comparison sort of a moving camera's young
// pixels took 3-4 ms on the frame loop's critical path. Returns what is left of the budget.
int64_t serve_young(const std::vector<uint8_t>& want, const std::vector<uint8_t>& ranks,
                    int64_t budget, std::vector<uint8_t>& extra) {
    constexpr int kMax = ExtraSamplePlan::kMaxTargeted, kBuckets = kMax * 64;
    std::vector<uint32_t> start(kBuckets + 1, 0);
    const auto bucket = [&](std::size_t i) { return (kMax - want[i]) * 64 + ranks[i]; };
    for (std::size_t i = 0; i < want.size(); ++i)
        if (want[i] > 0) ++start[std::size_t(bucket(i)) + 1];
    for (int b = 0; b < kBuckets; ++b)
        start[b + 1] += start[b];
    std::vector<uint32_t> order(start[kBuckets]);
    for (std::size_t i = 0; i < want.size(); ++i)
        if (want[i] > 0) order[start[bucket(i)]++] = uint32_t(i);
    for (int round = 1; round <= kMax && budget > 0; ++round)
        for (std::size_t k = 0; k < order.size() && budget > 0; ++k)
            if (want[order[k]] >= round) {
                ++extra[order[k]];
                --budget;
            }
    return budget;
}

}  // namespace

std::vector<uint8_t> plan_extra_samples(const std::vector<float>& history_frames, int width,
                                        int height, double budget, uint64_t frame) {
    const std::size_t pixels = std::size_t(std::max(width, 0)) * std::size_t(std::max(height, 0));
    std::vector<uint8_t> extra(pixels, 0);
    if (pixels == 0 || !(budget > 0.0)) return extra;
    int64_t left = std::llround(std::min(budget, 1.0) * double(pixels));
    const std::vector<uint8_t> ranks = dither_ranks(width, height, frame);
    if (history_frames.size() == pixels)
        left =
            serve_young(spread_wants(own_wants(history_frames), width, height), ranks, left, extra);
    // The dither's threshold: the largest that spends no more than what is left.
    const int threshold = int(std::min<int64_t>(64, left * 64 / int64_t(pixels)));
    for (std::size_t i = 0; i < pixels; ++i)
        if (ranks[i] < threshold) ++extra[i];
    return extra;
}

std::vector<float> sample_weights(const std::vector<uint8_t>& extra, int spp) {
    std::vector<float> weights(extra.size());
    for (std::size_t i = 0; i < extra.size(); ++i)
        weights[i] = float(spp + extra[i]) / float(spp);
    return weights;
}

}  // namespace pathfarm::coord
