// Floating-point helpers: robust secondary-ray origins and safe arithmetic.
#pragma once

#include <bit>
#include <cstdint>

#include "common/math/types.h"

namespace pathfarm {

// Moves a surface point p off its surface along the geometric normal n by a few ULPs, scaled
// with the magnitude of p, so secondary rays neither re-hit their own triangle nor leak through
// thin geometry. This is Wächter & Binder, "A Fast and Robust Method for Avoiding
// Self-Intersection" (Ray Tracing Gems, ch. 6): integer ULP steps far from the origin, a small
// float step near it. Pass n facing the side the new ray leaves towards.
inline Vec3 offset_ray_origin(const Vec3& p, const Vec3& n) {
    constexpr float kOrigin = 1.0f / 32.0f;
    constexpr float kFloatScale = 1.0f / 65536.0f;
    constexpr float kIntScale = 256.0f;
    Vec3 out;
    for (int i = 0; i < 3; ++i) {
        const auto of_i = static_cast<int32_t>(kIntScale * n[i]);
        const int32_t bits = std::bit_cast<int32_t>(p[i]);
        const float p_i = std::bit_cast<float>(bits + (p[i] < 0.0f ? -of_i : of_i));
        out[i] = std::abs(p[i]) < kOrigin ? p[i] + kFloatScale * n[i] : p_i;
    }
    return out;
}

inline float safe_sqrt(float x) { return std::sqrt(std::max(0.0f, x)); }
inline float sqr(float x) { return x * x; }

}  // namespace pathfarm
