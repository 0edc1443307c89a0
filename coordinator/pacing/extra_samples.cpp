// The extra-sample plan: young pixels first, round by round, then an ordered dither.
#include "coordinator/pacing/extra_samples.h"

#include <algorithm>
#include <cmath>

namespace pathfarm::coord {
namespace {

// The least history within kReach pixels of each pixel (a separable min filter).
std::vector<float> youngest_nearby(const std::vector<float>& history, int width, int height) {
    constexpr int r = ExtraSamplePlan::kReach;
    std::vector<float> rows(history.size()), out(history.size());
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            float m = history[std::size_t(y) * width + x];
            for (int d = std::max(0, x - r); d <= std::min(width - 1, x + r); ++d)
                m = std::min(m, history[std::size_t(y) * width + d]);
            rows[std::size_t(y) * width + x] = m;
        }
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            float m = rows[std::size_t(y) * width + x];
            for (int d = std::max(0, y - r); d <= std::min(height - 1, y + r); ++d)
                m = std::min(m, rows[std::size_t(d) * width + x]);
            out[std::size_t(y) * width + x] = m;
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
std::vector<int> dither_ranks(int width, int height, uint64_t frame) {
    const int ox = int((frame * 3) % 8), oy = int((frame * 5 + frame / 8) % 8);
    std::vector<int> ranks(std::size_t(width) * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            ranks[std::size_t(y) * width + x] = bayer_rank((x + ox) & 7, (y + oy) & 7);
    return ranks;
}

// Gives young pixels what they want, round by round and youngest first (ties by dither rank,
// so an even cut of a uniformly young frame is spread over it). Returns what is left.
int64_t serve_young(const std::vector<float>& young, const std::vector<int>& ranks, int64_t budget,
                    std::vector<uint8_t>& extra) {
    std::vector<uint8_t> want(young.size(), 0);
    std::vector<uint32_t> order;
    for (std::size_t i = 0; i < young.size(); ++i) {
        const float w = std::floor(ExtraSamplePlan::kWantedFrames - young[i]);
        want[i] = uint8_t(std::clamp(int(w), 0, ExtraSamplePlan::kMaxTargeted));
        if (want[i] > 0) order.push_back(uint32_t(i));
    }
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        if (young[a] != young[b]) return young[a] < young[b];
        return ranks[a] != ranks[b] ? ranks[a] < ranks[b] : a < b;
    });
    for (int round = 1; round <= ExtraSamplePlan::kMaxTargeted && budget > 0; ++round)
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
    const std::vector<int> ranks = dither_ranks(width, height, frame);
    if (history_frames.size() == pixels)
        left = serve_young(youngest_nearby(history_frames, width, height), ranks, left, extra);
    // The dither's threshold: the largest that spends no more than what is left.
    const int threshold = int(std::min<int64_t>(64, left * 64 / int64_t(pixels)));
    for (std::size_t i = 0; i < pixels; ++i)
        if (ranks[i] < threshold) ++extra[i];
    return extra;
}

}  // namespace pathfarm::coord
