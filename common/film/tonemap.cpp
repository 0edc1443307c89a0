// ACES-fitted tonemapping to 8-bit sRGB.
#include "common/film/tonemap.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

namespace pathfarm {
namespace {

// Above 1e6 the fit is past 1 (its limit is 2.51 / 2.43) and is clamped to it; the limit
// keeps x * x finite, which from about 1e19 up made the ratio inf / inf: a very bright pixel
// showed black.
float aces_fit(float x) {
    x = std::clamp(x, 0.0f, 1e6f);
    return std::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

float encode_srgb(float v) {
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

// The 8-bit code by table (the coordinator encodes every frame for its clients: a pow and a
// rounding per channel were 10 % of its CPU in the demo). The floats of [0, 1] are cut into
// buckets by their top 16 bits (exponent and 7 bits of mantissa, each bucket under 0.8 % wide),
// and no bucket holds more than one step of the code: the steps lie 0.9 % apart at 1 and
// wider below. A bucket keeps the code of its first float and the float where the code
// steps, if it does. Built from the definition, srgb8_reference(), by bisecting the floats'
// bit patterns (they order as the non-negative floats do);
// tests/unit/common/film/tonemap_test.cpp checks both agree.
constexpr uint32_t kOneBits = 0x3f800000u;  // 1.0f
constexpr int kBucketShift = 16;

struct CodeTable {
    std::vector<uint8_t> base;  // the code at the bucket's first float
    std::vector<float> step;    // the first float of the bucket with the next code, or +inf
    CodeTable() : base((kOneBits >> kBucketShift) + 1), step(base.size(), INFINITY) {
        const auto code = [](uint32_t bits) { return srgb8_reference(std::bit_cast<float>(bits)); };
        for (uint32_t b = 0; b < base.size(); ++b) {
            uint32_t lo = b << kBucketShift;
            const uint32_t last = std::min(kOneBits, lo + (1u << kBucketShift) - 1);
            const int first_code = code(lo);
            base[b] = uint8_t(first_code);
            if (code(last) == first_code) continue;
            for (uint32_t hi = last; lo < hi;) {
                const uint32_t mid = lo + (hi - lo) / 2;
                if (code(mid) > first_code)
                    hi = mid;
                else
                    lo = mid + 1;
            }
            step[b] = std::bit_cast<float>(lo);
        }
    }
};

const CodeTable& code_table() {
    static const CodeTable table;
    return table;
}

// The table's code for a display value in [-0, 1] (-0 as +0), without branches.
uint8_t table_code(const CodeTable& t, float display) {
    const uint32_t b = (std::bit_cast<uint32_t>(display) & 0x7fffffffu) >> kBucketShift;
    return uint8_t(t.base[b] + (display >= t.step[b] ? 1 : 0));
}

uint8_t code_of(const CodeTable& t, float display) {
    if (!(display > 0.0f)) return 0;  // NaN too
    if (display >= 1.0f) return 255;
    return table_code(t, display);
}

// aces_fit(exposed) for a run of floats, written with min and max (what std::clamp is for
// numbers) and |v| <= FLT_MAX for isfinite, so the loop vectorises (with -fno-trapping-math:
// CMakeLists.txt): the same operations in the same order, so the same floats.
void aces_fit_run(const float* __restrict in, float* __restrict out, std::size_t n,
                  float exposure) {
    for (std::size_t j = 0; j < n; ++j) {
        const float v = in[j], exposed = v * exposure;
        float x = std::abs(v) <= std::numeric_limits<float>::max() ? exposed : 0.0f;
        x = std::min(std::max(x, 0.0f), 1e6f);
        const float r = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
        out[j] = std::min(std::max(r, 0.0f), 1.0f);
    }
}

}  // namespace

uint8_t srgb8_code(float display) { return code_of(code_table(), display); }

int srgb8_reference(float display) { return int(std::lround(255.0f * encode_srgb(display))); }

uint8_t tonemap_channel(float linear, float exposure) {
    return srgb8_code(aces_fit(std::isfinite(linear) ? linear * exposure : 0.0f));
}

// By runs of floats: the fit vectorised into a buffer, then the table (the coordinator
// tonemaps every frame for its clients: one channel at a time it was 1.5 ms at 320x180).
void tonemap_rows_to_srgb8(const FloatImage& image, float exposure, int y0, int y1, uint8_t* out) {
    const CodeTable& table = code_table();
    const std::size_t row = std::size_t(std::max(image.width, 0)) * 3;
    const std::size_t begin = row * std::size_t(std::clamp(y0, 0, image.height));
    const std::size_t end = row * std::size_t(std::clamp(y1, 0, image.height));
    constexpr std::size_t kRun = 512;
    float display[kRun];
    for (std::size_t i = begin; i < end; i += kRun) {
        const std::size_t n = std::min(kRun, end - i);
        aces_fit_run(image.rgb.data() + i, display, n, exposure);
        for (std::size_t j = 0; j < n; ++j)  // the fit's values lie in [-0, 1], no NaN
            out[i + j] = table_code(table, display[j]);
    }
}

std::vector<uint8_t> tonemap_to_srgb8(const FloatImage& image, float exposure) {
    std::vector<uint8_t> out(image.rgb.size());
    tonemap_rows_to_srgb8(image, exposure, 0, image.height, out.data());
    return out;
}

}  // namespace pathfarm
