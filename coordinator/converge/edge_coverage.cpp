// Edge pixels found per row in parallel; each edge pixel's sides read from the unchanged image
// and written after all are computed, so no pixel reads another's new value.
#include "coordinator/converge/edge_coverage.h"

#include <algorithm>
#include <utility>

#include "coordinator/converge/parallel_rows.h"

namespace pathfarm::coord {
namespace {

// One row of the surfaces and distances with the rows above and below, and the row's outputs.
struct Rows {
    const uint32_t *s, *s_up, *s_down;
    const float *d, *d_up, *d_down;
    uint8_t *across, *behind, *on_edge;
};

// Pixel x of the row, its left and right neighbours at `left` and `right`.
inline void classify(const Rows& r, int x, int left, int right) {
    const uint32_t s = r.s[x];
    const float d = r.d[x];
    const bool o0 = r.s_up[x] != s, o1 = r.s_down[x] != s, o2 = r.s[left] != s,
               o3 = r.s[right] != s;
    r.across[x] = uint8_t(int(o0) + int(o1) + int(o2) + int(o3));
    r.behind[x] = uint8_t((o0 & (r.d_up[x] < d)) | (o1 & (r.d_down[x] < d)) |
                          (o2 & (r.d[left] < d)) | (o3 & (r.d[right] < d)));
    r.on_edge[x] = uint8_t(o0 | o1 | o2 | o3);
}

float luminance_at(const FloatImage& image, std::size_t i) {
    return luminance(Rgb(image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]));
}

}  // namespace

void EdgeCoverage::set_surfaces(const std::vector<uint32_t>& surface,
                                const std::vector<float>& distance,
                                const std::vector<uint8_t>& keep, int width, int height) {
    width_ = width;
    height_ = height;
    surface_ = surface;
    distance_ = distance;
    keep_ = keep;
    const std::size_t n = surface.size();
    on_edge_.resize(n);
    across_.resize(n);
    behind_.resize(n);
    // The image's border replicated: a missing neighbour is the pixel itself, never across.
    parallel_rows(height, [&](int y) {
        const std::size_t row = std::size_t(y) * width;
        const std::size_t up = std::size_t(std::max(0, y - 1)) * width,
                          down = std::size_t(std::min(height - 1, y + 1)) * width;
        const Rows r{&surface_[row],  &surface_[up],  &surface_[down],
                     &distance_[row], &distance_[up], &distance_[down],
                     &across_[row],   &behind_[row],  &on_edge_[row]};
        classify(r, 0, 0, std::min(1, width - 1));
        for (int x = 1; x + 1 < width; ++x)  // no clamps: it vectorises
            classify(r, x, x - 1, x + 1);
        if (width > 1) classify(r, width - 1, width - 2, width - 1);
    });
    edges_.clear();
    for (std::size_t i = 0; i < n; ++i)
        if (behind_[i] & !keep_[i]) edges_.push_back(uint32_t(i));
}

// Both sides' light at pixel i in one pass over its 5x5 window: its own surface (`behind`)
// and the nearer ones across the edge (`front`). Each is the pixel of median luminance among
// that side's pixels in the window that are not on an edge themselves (their light is their
// surface's alone), or else among its 3x3: the median, since a pixel beside the edge may hold a
// sample of the other side too. False when a side has no pixel there.
bool EdgeCoverage::sides(const FloatImage& image, std::size_t i, Rgb& behind, Rgb& front) const {
    const int x = int(i % std::size_t(width_)), y = int(i / std::size_t(width_));
    // [side][0: interior of the 5x5, 1: any of the 3x3]
    std::pair<float, uint32_t> found[2][2][24];
    int count[2][2] = {};
    for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width_ || ny >= height_) continue;
            const std::size_t j = std::size_t(ny) * width_ + nx;
            const bool own = surface_[j] == surface_[i];
            if (keep_[j] || (!own && !(distance_[j] < distance_[i]))) continue;
            const bool near = dx >= -1 && dx <= 1 && dy >= -1 && dy <= 1;
            if (!on_edge_[j] || near) {
                const std::pair<float, uint32_t> entry{luminance_at(image, j), uint32_t(j)};
                const int side = own ? 0 : 1;
                if (!on_edge_[j]) found[side][0][count[side][0]++] = entry;
                if (near) found[side][1][count[side][1]++] = entry;
            }
        }
    Rgb* out[2] = {&behind, &front};
    for (int side = 0; side < 2; ++side) {
        const int set = count[side][0] > 0 ? 0 : 1;
        const int n = count[side][set];
        if (n == 0) return false;
        auto* f = found[side][set];
        std::nth_element(f, f + n / 2, f + n);
        const std::size_t j = f[n / 2].second;
        *out[side] = Rgb(image.rgb[3 * j], image.rgb[3 * j + 1], image.rgb[3 * j + 2]);
    }
    return true;
}

Rgb EdgeCoverage::blended(const FloatImage& image, std::size_t i, float frames) const {
    const Rgb own(image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]);
    Rgb behind, front;
    if (!sides(image, i, behind, front)) return own;
    // Which side the pixel's sample saw: the nearer in luminance.
    const float l = luminance(own);
    if (std::abs(l - luminance(front)) >= std::abs(l - luminance(behind))) return own;
    const float c = std::min(0.5f, o_.coverage_per_side * float(across_[i]));
    const Rgb mix = (1.0f - c) * behind + c * front;
    const float w = o_.model_frames / (o_.model_frames + std::max(1.0f, frames));
    return (1.0f - w) * own + w * mix;
}

void EdgeCoverage::apply(FloatImage& image, const std::vector<float>& frames) {
    if (o_.model_frames <= 0.0f || image.width != width_ || image.height != height_ ||
        frames.size() != surface_.size())
        return;
    blended_.resize(edges_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, edges_.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t e = range.begin(); e < range.end(); ++e)
                              blended_[e] = blended(image, edges_[e], frames[edges_[e]]);
                      });
    for (std::size_t e = 0; e < edges_.size(); ++e)
        for (int c = 0; c < 3; ++c)
            image.rgb[3 * std::size_t(edges_[e]) + c] = blended_[e][c];
}

}  // namespace pathfarm::coord
