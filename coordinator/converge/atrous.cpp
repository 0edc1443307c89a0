// The à-trous levels, laid out for the vectoriser: padded float planes, one pass per row with
// every tap of a pixel unrolled in registers (no bounds checks, no sums in memory). The row
// function is a template on the vector width, instantiated for x86-64-v4 (16 lanes of AVX-512,
// whose 32 registers hold every sum and centre value without spilling), x86-64-v3 (8 lanes,
// AVX2 with FMA) and the baseline (8 lanes in SSE quarters), and picked once at load time.
// The luminance tolerance is computed inside the row pass from the variance rows around it.
// Rows run in parallel (TBB).
#include "coordinator/converge/atrous.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>

#include <xmmintrin.h>

#include "common/math/transform.h"
#include "coordinator/converge/parallel_rows.h"
#include "coordinator/converge/vector_lanes.h"

namespace pathfarm::coord {
namespace {

using namespace lanes;

// B-spline kernels: 3x3 (radius 1) and SVGF's 5x5 (radius 2), centre at index radius.
constexpr float kB2[3] = {1.0f / 4.0f, 1.0f / 2.0f, 1.0f / 4.0f};
constexpr float kB3[5] = {1.0f / 16.0f, 1.0f / 4.0f, 3.0f / 8.0f, 1.0f / 4.0f, 1.0f / 16.0f};
constexpr float kLuminanceEpsilon = 1e-6f;
constexpr float kPlaneSlope = 0.05f;  // about 3 degrees of shading-normal tilt
constexpr int kMaxTaps = 24;

float kernel(int radius, int t) { return radius == 1 ? kB2[t + 1] : kB3[t + 2]; }

// A row's planes, each pointing at the row's first pixel (padded layout). The variance's rows
// above and below, for the luminance tolerance.
struct Row {
    const float *nx, *ny, *nz, *z, *slope, *offset, *inv_plane;
    const float *r, *g, *b, *var, *var_up, *var_down;
    float *out_r, *out_g, *out_b, *out_var;
};

// A level's taps: index offsets, kernel weights and the plane tolerance's inverse growth (a tap
// further away may lie further off the centre's tangent plane on a curved or normal-mapped
// surface: one footprint plus kPlaneSlope per pixel of distance).
// Its tangent-plane step: how far the tap's film point lies from the centre's (dx, dy: in the
// film's units at unit depth, y up).
struct Taps {
    std::ptrdiff_t offset[kMaxTaps];
    float k[kMaxTaps], inv_distance[kMaxTaps], dx[kMaxTaps], dy[kMaxTaps];
    float k0;
    float sigma_l;  // the luminance edge, in standard deviations
};

// The weighted sums of a vector of centre pixels' taps, kept in registers.
template <typename V>
struct TapSums {
    V w, r, g, b, var;
};

// The centre pixels' values a tap weight needs.
template <typename V>
struct Centre {
    V nx, ny, nz, slope, offset, inv_plane, lum, inv_lum;
};

// Tap j of centres [x, x + lanes), unrolled at compile time.
template <typename V, int j>
[[gnu::always_inline]] inline void add_tap(const Row& a, const Taps& t, int x, const Centre<V>& c,
                                           TapSums<V>& s) {
    const std::ptrdiff_t q = x + t.offset[j];
    const V r = load<V>(a.r + q), g = load<V>(a.g + q), b = load<V>(a.b + q);
    V wn =
        vmax(V{}, c.nx * load<V>(a.nx + q) + c.ny * load<V>(a.ny + q) + c.nz * load<V>(a.nz + q));
    wn *= wn;  // ^128, written out
    wn *= wn;
    wn *= wn;
    wn *= wn;
    wn *= wn;
    wn *= wn;
    wn *= wn;
    // The tap's point is z_q (f_p + (dx, dy, 0)) in camera space (f: the film point at unit
    // depth), so n_p . point = z_q (n_p . f_p + n_p.x dx + n_p.y dy): one plane to read.
    const V plane = vabs(load<V>(a.z + q) * (c.slope + c.nx * t.dx[j] + c.ny * t.dy[j]) - c.offset);
    const V edge =
        plane * c.inv_plane * t.inv_distance[j] + vabs(c.lum - luminance(r, g, b)) * c.inv_lum;
    const V w = t.k[j] * wn * exp_nonpositive(-edge);
    s.w += w;
    s.r += w * r;
    s.g += w * g;
    s.b += w * b;
    s.var += w * w * load<V>(a.var + q);
}

// The variance's vertical 1-2-1 at column `at`. A function always inlined, not a lambda: a
// lambda is a function of its own, compiled for the baseline, and clang (at -O1) called it
// from the AVX-512 row with a vector return in the other ABI (garbage; AtrousIsa test).
template <typename V>
[[gnu::always_inline]] inline V variance_column(const Row& a, int at) {
    return 0.25f * (load<V>(a.var_up + at) + load<V>(a.var_down + at)) + 0.5f * load<V>(a.var + at);
}

// Centres [0, n) rounded up to whole vectors: the row's padding takes the excess (its zero
// inverse plane tolerance passes its zeros through).
template <typename V, int... j>
[[gnu::always_inline]] inline void filter_row_body(const Row& a, const Taps& t, int n,
                                                   std::integer_sequence<int, j...>) {
    constexpr int lanes = sizeof(V) / sizeof(float);
    // Flush denormals to zero: weights far across an edge (e^-80 and smaller, squared for the
    // variance) are denormal, and arithmetic on them cost about a fifth of the wavelet's time.
    const unsigned csr = _mm_getcsr();
    _mm_setcsr(csr | 0x8040);  // FTZ | DAZ
    for (int x = 0; x < n; x += lanes) {
        if (all_zero(load<V>(a.inv_plane + x))) {  // sky or sharp: every centre keeps its own
            store(a.out_r + x, load<V>(a.r + x));
            store(a.out_g + x, load<V>(a.g + x));
            store(a.out_b + x, load<V>(a.b + x));
            store(a.out_var + x, load<V>(a.var + x));
            continue;
        }
        Centre<V> c{load<V>(a.nx + x),
                    load<V>(a.ny + x),
                    load<V>(a.nz + x),
                    load<V>(a.slope + x),
                    load<V>(a.offset + x),
                    load<V>(a.inv_plane + x),
                    V{},
                    V{}};
        const V r = load<V>(a.r + x), g = load<V>(a.g + x), b = load<V>(a.b + x),
                var = load<V>(a.var + x);
        c.lum = luminance(r, g, b);
        // The luminance tolerance from the 3x3 Gaussian of the variance (SVGF's: less noisy
        // than one pixel's); the padding around the variance replicates the image's edge.
        const V v = 0.25f * (variance_column<V>(a, x - 1) + variance_column<V>(a, x + 1)) +
                    0.5f * variance_column<V>(a, x);
        c.inv_lum = 1.0f / (t.sigma_l * vsqrt(vmax(v, V{})) + kLuminanceEpsilon);
        TapSums<V> s{splat<V>(t.k0), t.k0 * r, t.k0 * g, t.k0 * b, (t.k0 * t.k0) * var};
        (add_tap<V, j>(a, t, x, c, s), ...);
        const auto filtered = c.inv_plane > 0.0f;
        const V inv_w = 1.0f / s.w;
        store(a.out_r + x, filtered ? s.r * inv_w : r);
        store(a.out_g + x, filtered ? s.g * inv_w : g);
        store(a.out_b + x, filtered ? s.b * inv_w : b);
        store(a.out_var + x, filtered ? s.var * inv_w * inv_w : var);
    }
    _mm_setcsr(csr);
}

// A row of 3x3 or 5x5 taps, in one of three instruction sets chosen once at start.
using FilterRow = void (*)(const Row&, const Taps&, int);

template <int taps>
__attribute__((target("arch=x86-64-v4"))) void filter_row_v4(const Row& a, const Taps& t, int n) {
    filter_row_body<vf16>(a, t, n, std::make_integer_sequence<int, taps>());
}
template <int taps>
__attribute__((target("arch=x86-64-v3"))) void filter_row_v3(const Row& a, const Taps& t, int n) {
    filter_row_body<vf8>(a, t, n, std::make_integer_sequence<int, taps>());
}
template <int taps>
void filter_row_baseline(const Row& a, const Taps& t, int n) {
    filter_row_body<vf8>(a, t, n, std::make_integer_sequence<int, taps>());
}

// The best set the CPU runs, or the one a test chose (use_atrous_isa).
AtrousIsa best_isa() {
    // By feature: clang 14 knows no "x86-64-v4" here. Every CPU with AVX2, FMA and BMI2 has
    // the rest of x86-64-v3 (F16C, LZCNT, MOVBE); x86-64-v4 adds these five AVX-512 sets.
    __builtin_cpu_init();
    const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                    __builtin_cpu_supports("bmi2");
    if (v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512vl"))
        return AtrousIsa::kX86_64_V4;
    return v3 ? AtrousIsa::kX86_64_V3 : AtrousIsa::kBaseline;
}

const AtrousIsa kBestIsa = best_isa();
std::atomic<AtrousIsa> g_isa{kBestIsa};

template <int taps>
FilterRow filter_row_for(AtrousIsa isa) {
    switch (isa) {
        case AtrousIsa::kX86_64_V4:
            return filter_row_v4<taps>;
        case AtrousIsa::kX86_64_V3:
            return filter_row_v3<taps>;
        case AtrousIsa::kBaseline:
            break;
    }
    return filter_row_baseline<taps>;
}

void filter_row_3x3(const Row& a, const Taps& t, int n) {
    filter_row_for<8>(g_isa.load(std::memory_order_relaxed))(a, t, n);
}

void filter_row_5x5(const Row& a, const Taps& t, int n) {
    filter_row_for<24>(g_isa.load(std::memory_order_relaxed))(a, t, n);
}

Taps taps_of(int radius, int step, std::ptrdiff_t stride, float pitch, float sigma_l) {
    Taps t{};
    t.k0 = kernel(radius, 0) * kernel(radius, 0);
    t.sigma_l = sigma_l;
    int j = 0;
    for (int ty = -radius; ty <= radius; ++ty)
        for (int tx = -radius; tx <= radius; ++tx) {
            if (tx == 0 && ty == 0) continue;
            t.offset[j] = std::ptrdiff_t(ty) * step * stride + std::ptrdiff_t(tx) * step;
            t.k[j] = kernel(radius, tx) * kernel(radius, ty);
            t.dx[j] = pitch * float(tx * step);
            t.dy[j] = -pitch * float(ty * step);  // rows go down, the film's y up
            t.inv_distance[j] =
                1.0f / (1.0f + kPlaneSlope * float(step) * std::sqrt(float(tx * tx + ty * ty)));
            ++j;
        }
    return t;
}

}  // namespace

bool use_atrous_isa(AtrousIsa isa) {
    if (int(isa) > int(kBestIsa)) return false;
    g_isa.store(isa, std::memory_order_relaxed);
    return true;
}

AtrousIsa atrous_isa() { return g_isa.load(std::memory_order_relaxed); }

void AtrousFilter::allocate(int width, int height, int pad) {
    width_ = width;
    height_ = height;
    pad_ = pad;
    stride_ = width_ + 2 * pad_;
    const std::size_t n = std::size_t(stride_) * std::size_t(height_ + 2 * pad_);
    float** planes[] = {&nx_,        &ny_,        &nz_,        &z_,         &slope_,
                        &offset_,    &inv_plane_, &rgb_[0][0], &rgb_[0][1], &rgb_[0][2],
                        &rgb_[1][0], &rgb_[1][1], &rgb_[1][2], &var_[0],    &var_[1]};
    constexpr std::size_t kPage = 1024, kStagger = 16;  // in floats: 4 KiB, 64 bytes
    const std::size_t plane = (n + kPage - 1) / kPage * kPage + kStagger;
    // Zeroed, and the padding stays zero (a zero normal is no one's tap); the buffer starts on
    // a page boundary.
    planes_ = HugePageBuffer(plane * std::size(planes) * sizeof(float));
    float* const first = static_cast<float*>(planes_.data());
    for (std::size_t p = 0; p < std::size(planes); ++p)
        *planes[p] = first + p * plane;
}

void AtrousFilter::filter(FloatImage& image, const std::vector<float>& variance, bool spatial,
                          const std::vector<Rgb>& modulate) {
    const float sigma_l = spatial ? o_.sigma_luminance_spatial : o_.sigma_luminance;
    parallel_rows(height_, [&](int y) {
        for (int x = 0; x < width_; ++x) {
            const std::size_t i = std::size_t(y) * width_ + x;
            const std::size_t k = std::size_t(y + pad_) * stride_ + pad_ + x;
            for (int c = 0; c < 3; ++c)
                rgb_[0][c][k] = image.rgb[3 * i + c];
            var_[0][k] = variance[i];
        }
    });
    replicate_edges(var_[0]);
    int from = 0;
    for (int l = 0; l < o_.levels; ++l, from = 1 - from)
        level(1 << l, from, sigma_l);
    parallel_rows(height_, [&](int y) {
        const std::size_t row = std::size_t(y) * width_;
        const std::size_t k0 = std::size_t(y + pad_) * stride_ + pad_;
        float* out = &image.rgb[3 * row];
        const Rgb* m = &modulate[row];
        for (int x = 0; x < width_; ++x)
            for (int c = 0; c < 3; ++c)
                out[3 * x + c] = rgb_[from][c][k0 + x] * m[x][c];
    });
}

// The pixels around the image (one on each side) take their nearest edge pixel's value.
void AtrousFilter::replicate_edges(float* plane) const {
    const auto row_start = [&](int y) { return plane + std::size_t(y + pad_) * stride_ + pad_; };
    for (int y = 0; y < height_; ++y) {
        float* row = row_start(y);
        row[-1] = row[0];
        row[width_] = row[width_ - 1];
    }
    std::copy(row_start(0) - 1, row_start(0) + width_ + 1, row_start(-1) - 1);
    std::copy(row_start(height_ - 1) - 1, row_start(height_ - 1) + width_ + 1,
              row_start(height_) - 1);
}

// One level from planes `from` to 1 - from, one task per row; then the new variance's edges
// replicated for the next level's luminance tolerance.
void AtrousFilter::level(int step, int from, float sigma_l) {
    float* const(&in)[3] = rgb_[from];
    const float* var = var_[from];
    const Taps taps = taps_of(o_.radius, step, stride_, pitch_, sigma_l);
    const int to = 1 - from;
    parallel_rows(height_, [&](int y) {
        const std::size_t k = std::size_t(y + pad_) * stride_ + pad_;
        const Row row{&nx_[k],           &ny_[k],         &nz_[k],         &z_[k],
                      &slope_[k],        &offset_[k],     &inv_plane_[k],  &in[0][k],
                      &in[1][k],         &in[2][k],       &var[k],         &var[k - stride_],
                      &var[k + stride_], &rgb_[to][0][k], &rgb_[to][1][k], &rgb_[to][2][k],
                      &var_[to][k]};
        if (o_.radius == 1)
            filter_row_3x3(row, taps, width_);
        else
            filter_row_5x5(row, taps, width_);
    });
    replicate_edges(var_[to]);
}

}  // namespace pathfarm::coord
