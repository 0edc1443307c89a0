// The neighbourhood's box by separable min/max passes (rows, then columns with the blend), the
// history read bilinearly at each pixel's source.
#include "coordinator/converge/temporal_aa.h"

#include <algorithm>
#include <utility>

#include "common/film/resample.h"
#include "coordinator/converge/parallel_rows.h"

namespace pathfarm::coord {
namespace {

// Each float's min and max over its pixel and the pixels left and right of it (edges
// replicated), into `lo_plane` and `hi_plane`.
void row_min_max(const FloatImage& image, std::vector<float>& lo_plane,
                 std::vector<float>& hi_plane) {
    const int w = image.width, h = image.height;
    lo_plane.resize(image.rgb.size());
    hi_plane.resize(image.rgb.size());
    // Along a row's 3w floats a channel's neighbours are 3 floats away; the interior loop has no
    // clamps, so it vectorises.
    parallel_rows(h, [&](int y) {
        const float* in = &image.rgb[std::size_t(y) * w * 3];
        float* lo = &lo_plane[std::size_t(y) * w * 3];
        float* hi = &hi_plane[std::size_t(y) * w * 3];
        const int n = 3 * w;
        for (int j = 3; j + 3 < n; ++j) {
            lo[j] = std::min(std::min(in[j - 3], in[j + 3]), in[j]);
            hi[j] = std::max(std::max(in[j - 3], in[j + 3]), in[j]);
        }
        for (int c = 0; c < 3; ++c)
            for (const int j : {c, n - 3 + c}) {
                const float left = in[std::max(c, j - 3)], right = in[std::min(n - 3 + c, j + 3)];
                lo[j] = std::min(std::min(left, right), in[j]);
                hi[j] = std::max(std::max(left, right), in[j]);
            }
    });
}

}  // namespace

void TemporalAntialias::apply(FloatImage& image, const std::vector<Vec2>& sources) {
    const int w = image.width, h = image.height;
    const std::size_t floats = image.rgb.size();
    if (history_.width != w || history_.height != h || sources.size() * 3 != floats) {
        history_ = image;
        return;
    }
    row_min_max(image, row_min_, row_max_);
    carried_.resize(floats);
    // The new history is written beside the output as each row is blended (the rows below
    // still read the old one), not copied after.
    if (next_.width != w || next_.height != h) next_ = FloatImage(w, h);
    parallel_rows(h, [&](int y) {
        const std::size_t row = std::size_t(y) * w * 3;
        const std::size_t up = std::size_t(std::max(0, y - 1)) * w * 3,
                          down = std::size_t(std::min(h - 1, y + 1)) * w * 3;
        // The history where each pixel's surface was (a gather: scalar), or the new output
        // itself where there is none (the blend below then leaves it as it is).
        float* carried = &carried_[row];
        const float* now = &image.rgb[row];
        for (int x = 0; x < w; ++x) {
            const Vec2 s = sources[std::size_t(y) * w + x];
            if (s.x < 0.0f) {
                carried[3 * x] = now[3 * x], carried[3 * x + 1] = now[3 * x + 1];
                carried[3 * x + 2] = now[3 * x + 2];
                continue;
            }
            const Rgb history = sample_bilinear(history_, s.x, s.y);
            carried[3 * x] = history.x, carried[3 * x + 1] = history.y;
            carried[3 * x + 2] = history.z;
        }
        // Clamp to the 3x3 box and blend, over the row's floats (vectorises).
        const float *lo_up = &row_min_[up], *lo_mid = &row_min_[row], *lo_down = &row_min_[down];
        const float *hi_up = &row_max_[up], *hi_mid = &row_max_[row], *hi_down = &row_max_[down];
        float* out = &image.rgb[row];
        float* next = &next_.rgb[row];
        const float alpha = alpha_;
        for (int j = 0; j < 3 * w; ++j) {
            const float lo = std::min(std::min(lo_up[j], lo_down[j]), lo_mid[j]);
            const float hi = std::max(std::max(hi_up[j], hi_down[j]), hi_mid[j]);
            const float kept = std::min(std::max(carried[j], lo), hi);
            out[j] = next[j] = kept + alpha * (out[j] - kept);
        }
    });
    std::swap(history_, next_);
}

}  // namespace pathfarm::coord
