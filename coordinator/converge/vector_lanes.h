// Lanes in GCC's vector extensions for the converge filters' row passes, 8 or 16 floats: a
// function built for x86-64-v4 gets AVX-512 (16 lanes), one for x86-64-v3 AVX2 with FMA (8),
// the baseline two SSE halves of 8; none depends on the auto-vectoriser's if-conversion. The
// helpers are always inlined, so the ABI GCC warns about (-Wpsabi) is never used; include this
// only from sources built with -Wno-psabi (coordinator/CMakeLists.txt). That flag also hides
// the real case: a vector passed to or from a function that is not inlined (a lambda inside a
// target("arch=...") function is compiled for the baseline) crosses two ABIs and arrives as
// garbage; keep such helpers always_inline templates (AtrousIsa test).
#pragma once

#include <cstdint>
#include <cstring>

#include <emmintrin.h>

namespace pathfarm::coord::lanes {

// (A template alias cannot carry the vector_size attribute: GCC drops it.)
using vf8 = float __attribute__((vector_size(32)));
using vf16 = float __attribute__((vector_size(64)));
using vi8 = int32_t __attribute__((vector_size(32)));
constexpr int kMaxLanes = 16;

template <typename V>
[[gnu::always_inline]] inline V load(const float* p) {
    V v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
template <typename V>
[[gnu::always_inline]] inline void store(float* p, V v) {
    std::memcpy(p, &v, sizeof v);
}
template <typename V>
[[gnu::always_inline]] inline V splat(float f) {
    return V{} + f;
}
template <typename V>
[[gnu::always_inline]] inline V vmax(V a, V b) {
    return a > b ? a : b;
}
template <typename V>
[[gnu::always_inline]] inline V vabs(V a) {
    using I = decltype(a > a);
    return (V)((I)a & 0x7fffffff);
}
// Computed where needed rather than kept in a plane: three multiply-adds on colour the taps
// load anyway cost less than a plane more to read.
template <typename V>
[[gnu::always_inline]] inline V luminance(V r, V g, V b) {
    return 0.2126f * r + 0.7152f * g + 0.0722f * b;
}

// e^x for x <= 0 to about 3e-3 relative (plenty for a weight), without floor or table:
// 2^t = 2^i 2^f with i = trunc(t), f in (-1, 0], a degree-4 Taylor series.
template <typename V>
[[gnu::always_inline]] inline V exp_nonpositive(V x) {
    using I = decltype(x > x);
    const V t = vmax(x, splat<V>(-87.0f)) * 1.44269504f;
    const I i = __builtin_convertvector(t, I);
    const V f = t - __builtin_convertvector(i, V);
    const V p = 1.0f + f * (0.693147f + f * (0.240227f + f * (0.0555041f + f * 0.00961813f)));
    return p * (V)((i + 127) << 23);
}

// Whether every lane's bits are zero (+0.0f), in SSE2, which every function has.
template <typename V>
[[gnu::always_inline]] inline bool all_zero(V a) {
    __m128i quarter[sizeof(V) / sizeof(__m128i)];
    std::memcpy(quarter, &a, sizeof a);
    __m128i any = quarter[0];
    for (const __m128i& q : quarter)
        any = _mm_or_si128(any, q);
    return _mm_movemask_epi8(_mm_cmpeq_epi32(any, _mm_setzero_si128())) == 0xffff;
}

// SSE square roots of each 4 lanes: every function has SSE, and the vector extension has no
// sqrt.
template <typename V>
[[gnu::always_inline]] inline V vsqrt(V a) {
    __m128 quarter[sizeof(V) / sizeof(__m128)];
    std::memcpy(quarter, &a, sizeof a);
    for (__m128& q : quarter)
        q = _mm_sqrt_ps(q);
    std::memcpy(&a, quarter, sizeof a);
    return a;
}

}  // namespace pathfarm::coord::lanes
