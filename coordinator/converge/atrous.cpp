// The à-trous levels, laid out for the vectoriser: padded float planes, one pass per row with
// every tap of a pixel unrolled in registers (no bounds checks, no sums in memory), compiled
// three times (x86-64-v4, whose 32 vector registers hold every sum and centre value without
// spilling: 25 % less time than v3 on the development machine; x86-64-v3, i.e. AVX2 with FMA;
// baseline) and picked at load time. Rows run in parallel (TBB).
#include "coordinator/converge/atrous.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>

#include <xmmintrin.h>

#include "common/math/transform.h"
#include "coordinator/converge/parallel_rows.h"

namespace pathfarm::coord {
namespace {

// B-spline kernels: 3x3 (radius 1) and SVGF's 5x5 (radius 2), centre at index radius.
constexpr float kB2[3] = {1.0f / 4.0f, 1.0f / 2.0f, 1.0f / 4.0f};
constexpr float kB3[5] = {1.0f / 16.0f, 1.0f / 4.0f, 3.0f / 8.0f, 1.0f / 4.0f, 1.0f / 16.0f};
constexpr float kLuminanceEpsilon = 1e-6f;
constexpr float kPlaneSlope = 0.05f;  // about 3 degrees of shading-normal tilt
constexpr int kMaxTaps = 24;

float kernel(int radius, int t) { return radius == 1 ? kB2[t + 1] : kB3[t + 2]; }

// Eight lanes in GCC's vector extensions: the x86-64-v3 clone gets AVX2 with FMA, the baseline
// two SSE halves, and neither depends on the auto-vectoriser's if-conversion.
// The helpers are always inlined, so the ABI GCC warns about (-Wpsabi) is never used.
#pragma GCC diagnostic ignored "-Wpsabi"
using vf = float __attribute__((vector_size(32)));
using vi = int32_t __attribute__((vector_size(32)));
constexpr int kLanes = 8;

[[gnu::always_inline]] inline vf load(const float* p) {
    vf v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void store(float* p, vf v) { std::memcpy(p, &v, sizeof v); }
[[gnu::always_inline]] inline vf splat(float f) { return vf{} + f; }
[[gnu::always_inline]] inline vf vmax(vf a, vf b) { return a > b ? a : b; }
[[gnu::always_inline]] inline vf vabs(vf a) { return (vf)((vi)a & 0x7fffffff); }
// Computed where needed rather than kept in a plane: three multiply-adds on colour the taps
// load anyway cost less than a plane more to read.
[[gnu::always_inline]] inline vf luminance(vf r, vf g, vf b) {
    return 0.2126f * r + 0.7152f * g + 0.0722f * b;
}

// e^x for x <= 0 to about 3e-3 relative (plenty for a weight), without floor or table:
// 2^t = 2^i 2^f with i = trunc(t), f in (-1, 0], a degree-4 Taylor series.
[[gnu::always_inline]] inline vf exp_nonpositive(vf x) {
    const vf t = vmax(x, splat(-87.0f)) * 1.44269504f;
    const vi i = __builtin_convertvector(t, vi);
    const vf f = t - __builtin_convertvector(i, vf);
    const vf p = 1.0f + f * (0.693147f + f * (0.240227f + f * (0.0555041f + f * 0.00961813f)));
    return p * (vf)((i + 127) << 23);
}

// A row's planes, each pointing at the row's first pixel (padded layout).
struct Row {
    const float *nx, *ny, *nz, *z, *slope, *offset, *inv_plane, *inv_lum;
    const float *r, *g, *b, *var;
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
};

// The weighted sums of eight centre pixels' taps, kept in registers.
struct TapSums {
    vf w, r, g, b, var;
};

// The centre pixels' values a tap weight needs.
struct Centre {
    vf nx, ny, nz, slope, offset, inv_plane, lum, inv_lum;
};

// Tap j of centres [x, x + 8), unrolled at compile time.
template <int j>
[[gnu::always_inline]] inline void add_tap(const Row& a, const Taps& t, int x, const Centre& c,
                                           TapSums& s) {
    const std::ptrdiff_t q = x + t.offset[j];
    const vf r = load(a.r + q), g = load(a.g + q), b = load(a.b + q);
    vf wn = vmax(vf{}, c.nx * load(a.nx + q) + c.ny * load(a.ny + q) + c.nz * load(a.nz + q));
    wn *= wn;  // ^128, written out
    wn *= wn;
    wn *= wn;
    wn *= wn;
    wn *= wn;
    wn *= wn;
    wn *= wn;
    // The tap's point is z_q (f_p + (dx, dy, 0)) in camera space (f: the film point at unit
    // depth), so n_p . point = z_q (n_p . f_p + n_p.x dx + n_p.y dy): one plane to read.
    const vf plane = vabs(load(a.z + q) * (c.slope + c.nx * t.dx[j] + c.ny * t.dy[j]) - c.offset);
    const vf edge =
        plane * c.inv_plane * t.inv_distance[j] + vabs(c.lum - luminance(r, g, b)) * c.inv_lum;
    const vf w = t.k[j] * wn * exp_nonpositive(-edge);
    s.w += w;
    s.r += w * r;
    s.g += w * g;
    s.b += w * b;
    s.var += w * w * load(a.var + q);
}

// Centres [0, n) rounded up to whole lanes: the row's padding takes the excess (its zero
// inverse plane tolerance passes its zeros through).
template <int... j>
[[gnu::always_inline]] inline void filter_row_body(const Row& a, const Taps& t, int n,
                                                   std::integer_sequence<int, j...>) {
    // Flush denormals to zero: weights far across an edge (e^-80 and smaller, squared for the
    // variance) are denormal, and arithmetic on them cost about a fifth of the wavelet's time.
    const unsigned csr = _mm_getcsr();
    _mm_setcsr(csr | 0x8040);  // FTZ | DAZ
    for (int x = 0; x < n; x += kLanes) {
        Centre c{load(a.nx + x),     load(a.ny + x),        load(a.nz + x), load(a.slope + x),
                 load(a.offset + x), load(a.inv_plane + x), vf{},           load(a.inv_lum + x)};
        const vf r = load(a.r + x), g = load(a.g + x), b = load(a.b + x), var = load(a.var + x);
        c.lum = luminance(r, g, b);
        TapSums s{splat(t.k0), t.k0 * r, t.k0 * g, t.k0 * b, (t.k0 * t.k0) * var};
        (add_tap<j>(a, t, x, c, s), ...);
        const vi filtered = c.inv_plane > 0.0f;
        const vf inv_w = 1.0f / s.w;
        store(a.out_r + x, filtered ? s.r * inv_w : r);
        store(a.out_g + x, filtered ? s.g * inv_w : g);
        store(a.out_b + x, filtered ? s.b * inv_w : b);
        store(a.out_var + x, filtered ? s.var * inv_w * inv_w : var);
    }
    _mm_setcsr(csr);
}

__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"))) void filter_row_3x3(
    const Row& a, const Taps& t, int n) {
    filter_row_body(a, t, n, std::make_integer_sequence<int, 8>());
}

__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"))) void filter_row_5x5(
    const Row& a, const Taps& t, int n) {
    filter_row_body(a, t, n, std::make_integer_sequence<int, 24>());
}

Taps taps_of(int radius, int step, std::ptrdiff_t stride, float pitch) {
    Taps t{};
    t.k0 = kernel(radius, 0) * kernel(radius, 0);
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

void AtrousFilter::set_guide(const GBuffer& g, const Camera& camera,
                             const std::vector<uint8_t>& filter) {
    // The widest tap offset, and at least a lane's width for the rows' rounded-up ends.
    const int pad = std::max(kLanes, o_.radius << (o_.levels - 1));
    if (g.width != width_ || g.height != height_ || pad != pad_) {
        width_ = g.width;
        height_ = g.height;
        pad_ = pad;
        stride_ = width_ + 2 * pad_;
        const std::size_t n = std::size_t(stride_) * std::size_t(height_ + 2 * pad_);
        float** planes[] = {&nx_,        &ny_,        &nz_,        &z_,
                            &slope_,     &offset_,    &inv_plane_, &rgb_[0][0],
                            &rgb_[0][1], &rgb_[0][2], &rgb_[1][0], &rgb_[1][1],
                            &rgb_[1][2], &var_[0],    &var_[1],    &inv_lum_};
        constexpr std::size_t kPage = 1024, kStagger = 16;  // in floats: 4 KiB, 64 bytes
        const std::size_t plane = (n + kPage - 1) / kPage * kPage + kStagger;
        planes_.assign(plane * std::size(planes) + kPage, 0.0f);  // the padding stays zero
        // From the first page boundary in the allocation (a zero normal is no one's tap).
        const std::size_t first =
            (kPage - (reinterpret_cast<std::uintptr_t>(planes_.data()) / sizeof(float)) % kPage) %
            kPage;
        for (std::size_t p = 0; p < std::size(planes); ++p)
            *planes[p] = planes_.data() + first + p * plane;
    }
    // Camera space: normals rotated into it, points as depth along the view axis times the
    // pixel centre's film point (x, y, -1) at unit depth (generate_camera_ray's inverse).
    const Mat3 to_camera(glm::inverse(camera.camera_to_world));
    const float tan_half = std::tan(0.5f * camera.yfov_radians);
    pitch_ = 2.0f * tan_half / float(height_);
    const float film_x = 2.0f * tan_half * float(width_) / float(height_) / float(width_);
    const float inv_sigma_pitch = 1.0f / (o_.sigma_plane * pitch_);
    film_x_.resize(std::size_t(width_));
    for (int x = 0; x < width_; ++x)
        film_x_[std::size_t(x)] = (float(x) + 0.5f) * film_x - 0.5f * float(width_) * film_x;
    parallel_rows(height_, [&](int y) {
        const float fy = (1.0f - 2.0f * (float(y) + 0.5f) / float(height_)) * tan_half;
        const std::size_t row = std::size_t(y) * width_;
        const std::size_t k0 = std::size_t(y + pad_) * stride_ + pad_;
        for (int x = 0; x < width_; ++x) {
            const std::size_t i = row + x, k = k0 + x;
            if (!filter[i]) {
                nx_[k] = ny_[k] = nz_[k] = z_[k] = slope_[k] = offset_[k] = inv_plane_[k] = 0.0f;
                continue;
            }
            const Vec3 n = glm::normalize(to_camera * g.normal[i]);
            const float fx = film_x_[std::size_t(x)];
            const float z = g.distance[i] / std::sqrt(fx * fx + fy * fy + 1.0f);
            const float slope = n.x * fx + n.y * fy - n.z;  // n . (fx, fy, -1)
            nx_[k] = n.x;
            ny_[k] = n.y;
            nz_[k] = n.z;
            z_[k] = z;
            slope_[k] = slope;
            offset_[k] = z * slope;
            inv_plane_[k] = inv_sigma_pitch / g.distance[i];
        }
    });
}

void AtrousFilter::filter(FloatImage& image, const std::vector<float>& variance, bool spatial) {
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
    int from = 0;
    for (int l = 0; l < o_.levels; ++l, from = 1 - from)
        level(1 << l, from, sigma_l);
    parallel_rows(height_, [&](int y) {
        for (int x = 0; x < width_; ++x) {
            const std::size_t i = std::size_t(y) * width_ + x;
            const std::size_t k = std::size_t(y + pad_) * stride_ + pad_ + x;
            for (int c = 0; c < 3; ++c)
                image.rgb[3 * i + c] = rgb_[from][c][k];
        }
    });
}

// One level from planes `from` to 1 - from, one task per row: the centre row's luminance
// tolerance (from the 3x3 Gaussian of the variance, edges replicated: SVGF's, less noisy than
// one pixel's), then the taps.
void AtrousFilter::level(int step, int from, float sigma_l) {
    float* const(&in)[3] = rgb_[from];
    const float* var = var_[from];
    const int w = width_, h = height_;
    const auto row_start = [&](int y) { return std::size_t(y + pad_) * stride_ + pad_; };
    const Taps taps = taps_of(o_.radius, step, stride_, pitch_);
    const int to = 1 - from;
    parallel_rows(h, [&](int y) {
        const std::size_t k = row_start(y);
        const float* rows[3] = {&var[row_start(std::max(0, y - 1))], &var[k],
                                &var[row_start(std::min(h - 1, y + 1))]};
        float* inv_lum = &inv_lum_[k];
        const float *up = rows[0], *mid = rows[1], *down = rows[2];
        const float sigma = sigma_l;
        // Vertical then horizontal weights; the row's two ends replicate their edge pixel.
        const auto column = [&](int x) { return 0.25f * (up[x] + down[x]) + 0.5f * mid[x]; };
        const auto tolerance = [&](float v) {
            return 1.0f / (sigma * std::sqrt(std::max(0.0f, v)) + kLuminanceEpsilon);
        };
        for (int x = 1; x + 1 < w; ++x) {
            const float v = 0.25f * (0.25f * (up[x - 1] + down[x - 1]) + 0.5f * mid[x - 1]) +
                            0.5f * (0.25f * (up[x] + down[x]) + 0.5f * mid[x]) +
                            0.25f * (0.25f * (up[x + 1] + down[x + 1]) + 0.5f * mid[x + 1]);
            inv_lum[x] = tolerance(v);
        }
        inv_lum[0] = tolerance(0.75f * column(0) + 0.25f * column(std::min(1, w - 1)));
        inv_lum[w - 1] = tolerance(0.75f * column(w - 1) + 0.25f * column(std::max(0, w - 2)));
        const Row row{&nx_[k],         &ny_[k],         &nz_[k],         &z_[k],
                      &slope_[k],      &offset_[k],     &inv_plane_[k],  &inv_lum_[k],
                      &in[0][k],       &in[1][k],       &in[2][k],       &var[k],
                      &rgb_[to][0][k], &rgb_[to][1][k], &rgb_[to][2][k], &var_[to][k]};
        if (o_.radius == 1)
            filter_row_3x3(row, taps, w);
        else
            filter_row_5x5(row, taps, w);
    });
}

}  // namespace pathfarm::coord
