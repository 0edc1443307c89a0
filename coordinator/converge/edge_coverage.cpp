// Edge pixels found per row in parallel; each edge pixel's sides read from the unchanged image
// and written after all are computed, so no pixel reads another's new value.
#include "coordinator/converge/edge_coverage.h"

#include <algorithm>
#include <bit>
#include <cstdint>

#include "coordinator/converge/parallel_rows.h"

namespace pathfarm::coord {
namespace {

// Pixels [begin, end) of one row: how many of their 4-neighbours see another surface, whether
// one of those is nearer, whether any is. `left` and `right` offset the horizontal neighbours
// (0 at the image's border, which is replicated). Restrict pointers and no branches: it
// vectorises.
void classify(const uint32_t* __restrict s, const uint32_t* __restrict s_up,
              const uint32_t* __restrict s_down, const float* __restrict d,
              const float* __restrict d_up, const float* __restrict d_down,
              uint8_t* __restrict across, uint8_t* __restrict behind, uint8_t* __restrict on_edge,
              int begin, int end, int left, int right) {
    for (int x = begin; x < end; ++x) {
        const uint32_t here = s[x];
        const float depth = d[x];
        const int o0 = s_up[x] != here, o1 = s_down[x] != here, o2 = s[x + left] != here,
                  o3 = s[x + right] != here;
        across[x] = uint8_t(o0 + o1 + o2 + o3);
        behind[x] = uint8_t((o0 & int(d_up[x] < depth)) | (o1 & int(d_down[x] < depth)) |
                            (o2 & int(d[x + left] < depth)) | (o3 & int(d[x + right] < depth)));
        on_edge[x] = uint8_t(o0 | o1 | o2 | o3);
    }
}

}  // namespace

void EdgeCoverage::set_surfaces(const std::vector<uint32_t>& surface,
                                const std::vector<float>& distance,
                                const std::vector<uint8_t>& filtered, int width, int height) {
    width_ = width;
    height_ = height;
    const std::size_t n = surface.size();
    keep_.resize(n);
    on_edge_.resize(n);
    across_.resize(n);
    behind_.resize(n);
    // The image's border replicated: a missing neighbour is the pixel itself, never across.
    parallel_rows(height, [&](int y) {
        const std::size_t row = std::size_t(y) * width;
        const std::size_t up = std::size_t(std::max(0, y - 1)) * width,
                          down = std::size_t(std::min(height - 1, y + 1)) * width;
        const auto run = [&](int begin, int end, int left, int right) {
            classify(&surface[row], &surface[up], &surface[down], &distance[row], &distance[up],
                     &distance[down], &across_[row], &behind_[row], &on_edge_[row], begin, end,
                     left, right);
        };
        for (std::size_t i = row; i < row + std::size_t(width); ++i)
            keep_[i] = uint8_t(surface[i] != 0 && filtered[i] == 0);
        if (width == 1) return run(0, 1, 0, 0);
        run(0, 1, 0, 1);
        run(1, width - 1, -1, 1);
        run(width - 1, width, -1, 0);
    });
    edges_.clear();
    for (std::size_t i = 0; i < n; ++i)
        if (behind_[i] & !keep_[i]) edges_.push_back(uint32_t(i));
}

namespace {

// A pixel's luminance and index as one integer ordered as (luminance, index): the median's
// comparisons become one integer compare (the float compare with its tie-break cost a third of
// the sides' time). The float's bits are made to sort as unsigned integers (negative values
// flipped, positive ones above them).
uint64_t luminance_key(float luminance, uint32_t pixel) {
    const uint32_t bits = std::bit_cast<uint32_t>(luminance);
    const uint32_t ordered = (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
    return (uint64_t(ordered) << 32) | pixel;
}

}  // namespace

// Both sides' light at pixel i in one pass over its 5x5 window: its own surface (`behind`)
// and the nearer ones across the edge (`front`). Each is the pixel of median luminance among
// that side's pixels in the window that are not on an edge themselves (their light is their
// surface's alone), or else among its 3x3: the median, since a pixel beside the edge may hold a
// sample of the other side too. False when a side has no pixel there.
bool EdgeCoverage::sides(const FloatImage& image, const Surfaces& s, int x, int y, Rgb& behind,
                         Rgb& front, float behind_range[2]) const {
    const std::size_t i = std::size_t(y) * width_ + x;
    // [side][0: interior of the 5x5, 1: any of the 3x3]; ties in luminance broken by the
    // pixel's index (luminance_key): the same choice on every run.
    uint64_t found[2][2][24];  // not initialised: only the first count[side][set] are read
    int count[2][2] = {};
    const int x0 = std::max(0, x - 2), x1 = std::min(width_ - 1, x + 2);
    for (int ny = std::max(0, y - 2); ny <= std::min(height_ - 1, y + 2); ++ny) {
        const std::size_t row = std::size_t(ny) * width_;
        for (int nx = x0; nx <= x1; ++nx) {
            const std::size_t j = row + std::size_t(nx);
            const bool own = s.surface[j] == s.surface[i];
            if (j == i || keep_[j] || (!own && !(s.distance[j] < s.distance[i]))) continue;
            const bool near = std::abs(nx - x) <= 1 && std::abs(ny - y) <= 1;
            const int side = own ? 0 : 1;
            const uint64_t key = luminance_key(luminance_[j], uint32_t(j));
            if (!on_edge_[j]) found[side][0][count[side][0]++] = key;
            if (near) found[side][1][count[side][1]++] = key;
        }
    }
    Rgb* out[2] = {&behind, &front};
    for (int side = 0; side < 2; ++side) {
        const int set = count[side][0] > 0 ? 0 : 1;
        const int n = count[side][set];
        if (n == 0) return false;
        uint64_t* f = found[side][set];
        std::nth_element(f, f + n / 2, f + n);
        const std::size_t j = uint32_t(f[n / 2]);
        *out[side] = image.pixel(int(j % std::size_t(width_)), int(j / std::size_t(width_)));
        if (side == 0) {  // the behind side's least and largest luminance
            const auto [least, most] = std::minmax_element(f, f + n);
            behind_range[0] = luminance_[uint32_t(*least)];
            behind_range[1] = luminance_[uint32_t(*most)];
        }
    }
    return true;
}

Rgb EdgeCoverage::blended(const FloatImage& image, const Surfaces& s, std::size_t i,
                          float frames) const {
    const int x = int(i % std::size_t(width_)), y = int(i / std::size_t(width_));
    const Rgb own = image.pixel(x, y);
    Rgb behind, front;
    float range[2];
    if (!sides(image, s, x, y, behind, front, range)) return own;
    // Which side the pixel's sample saw: the nearer in luminance, or, for a pixel of one
    // frame (its own samples alone), the front when no pixel of its side in the window is
    // nearly as far from that side's median towards the front: a sample of a darker rim (a
    // limb's edge) can be nearer the background's light than the front's median and still be
    // no light the background shows (Cesium Man's black sky). Not over frames: a mix of
    // samples lies between the sides too.
    const float l = luminance(own);
    const float lb = luminance(behind), lf = luminance(front);
    const float margin = 0.02f * lb + 1e-3f;
    const bool beyond_behind =
        frames <= 1.0f && ((lf > lb && l > lb + 2.0f * (range[1] - lb) + margin) ||
                           (lf < lb && l < lb - 2.0f * (lb - range[0]) - margin));
    if (!beyond_behind && std::abs(l - lf) >= std::abs(l - lb)) return own;
    const float c = std::min(0.5f, o_.coverage_per_side * float(across_[i]));
    const Rgb mix = (1.0f - c) * behind + c * front;
    const float w = o_.model_frames / (o_.model_frames + std::max(1.0f, frames));
    return (1.0f - w) * own + w * mix;
}

void EdgeCoverage::apply(FloatImage& image, const std::vector<float>& frames,
                         const std::vector<uint32_t>& surface, const std::vector<float>& distance) {
    const std::size_t n = std::size_t(width_) * std::size_t(height_);
    if (o_.model_frames <= 0.0f || image.width != width_ || image.height != height_ ||
        frames.size() != n || surface.size() != n || distance.size() != n || keep_.size() != n)
        return;
    // Pixels whose history would leave the mix less than 1/16 of the weight are left as they
    // are: a still view's edges cost nothing once converged.
    const float most_frames = 15.0f * o_.model_frames;
    short_history_.clear();
    for (const uint32_t i : edges_)
        if (frames[i] <= most_frames) short_history_.push_back(i);
    if (short_history_.empty()) return;
    // Every pixel's luminance once (a window reads each about 25 times).
    const Surfaces surfaces{surface.data(), distance.data()};
    luminance_.resize(n);
    parallel_rows(height_, [&](int y) {
        const float* in = &image.rgb[std::size_t(y) * width_ * 3];
        float* out = &luminance_[std::size_t(y) * width_];
        for (int x = 0; x < width_; ++x)
            out[x] = luminance(Rgb(in[3 * x], in[3 * x + 1], in[3 * x + 2]));
    });
    blended_.resize(short_history_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, short_history_.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t e = range.begin(); e < range.end(); ++e)
                              blended_[e] = blended(image, surfaces, short_history_[e],
                                                    frames[short_history_[e]]);
                      });
    for (std::size_t e = 0; e < short_history_.size(); ++e) {
        const std::size_t i = short_history_[e];
        image.set_pixel(int(i % std::size_t(width_)), int(i / std::size_t(width_)), blended_[e]);
    }
}

}  // namespace pathfarm::coord
