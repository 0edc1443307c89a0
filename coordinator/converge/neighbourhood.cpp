// Row sums of the values and their squares, then column sums of those, over interleaved RGB.
#include "coordinator/converge/neighbourhood.h"

#include <algorithm>
#include <cmath>

#include "coordinator/converge/parallel_rows.h"

namespace pathfarm::coord {
namespace {

// Sums of three along a row of m interleaved floats (neighbours 3 apart); the ends have two.
void row_sums(const float* in, int m, float* s, float* s2) {
    if (m <= 3) {
        for (int j = 0; j < m; ++j) {
            s[j] = in[j];
            s2[j] = in[j] * in[j];
        }
        return;
    }
    for (int j = 0; j < 3; ++j) {
        s[j] = in[j] + in[j + 3];
        s2[j] = in[j] * in[j] + in[j + 3] * in[j + 3];
    }
    for (int j = 3; j < m - 3; ++j) {
        s[j] = in[j - 3] + in[j] + in[j + 3];
        s2[j] = in[j - 3] * in[j - 3] + in[j] * in[j] + in[j + 3] * in[j + 3];
    }
    for (int j = m - 3; j < m; ++j) {
        s[j] = in[j - 3] + in[j];
        s2[j] = in[j - 3] * in[j - 3] + in[j] * in[j];
    }
}

}  // namespace

void NeighbourhoodStats::compute(const FloatImage& image) {
    const int w = image.width, h = image.height, m = 3 * w;
    const std::size_t n = std::size_t(m) * std::size_t(h);
    for (std::vector<float>* p : {&sum_, &sum2_, &mean_, &sigma_})
        p->resize(n);
    parallel_rows(h, [&](int y) {
        const std::size_t row = std::size_t(y) * m;
        row_sums(&image.rgb[row], m, &sum_[row], &sum2_[row]);
    });
    parallel_rows(h, [&](int y) {
        const std::size_t row = std::size_t(y) * m;
        const float *s = &sum_[row], *s2 = &sum2_[row];
        const bool up = y > 0, down = y + 1 < h;
        const int rows_in = 1 + int(up) + int(down);
        float* mean = &mean_[row];
        float* sigma = &sigma_[row];
        // Floats [j0, j1) of the row, whose pixels have `cols_in` columns inside the image.
        const auto columns = [&](int j0, int j1, int cols_in) {
            const float inv_count = 1.0f / float(rows_in * cols_in);
            for (int j = j0; j < j1; ++j) {
                float t = s[j], t2 = s2[j];
                if (up) {
                    t += s[j - m];
                    t2 += s2[j - m];
                }
                if (down) {
                    t += s[j + m];
                    t2 += s2[j + m];
                }
                mean[j] = t * inv_count;
                sigma[j] = std::sqrt(std::max(t2 * inv_count - mean[j] * mean[j], 0.0f));
            }
        };
        if (w == 1) {
            columns(0, m, 1);
        } else {
            columns(0, 3, 2);
            columns(3, m - 3, 3);
            columns(m - 3, m, 2);
        }
    });
}

}  // namespace pathfarm::coord
