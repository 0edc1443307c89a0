// Floating-point helpers: robust secondary-ray origins and safe arithmetic.
#pragma once

#include <bit>
#include <cstdint>

#include "common/math/types.h"

namespace pathfarm {

// The largest float below 1: a sample in [0,1) clamped here stays in [0,1) (pbrt's
// OneMinusEpsilon).
inline constexpr float kOneBelow = 0x1.fffffep-1f;

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

// The shadow ray between two surface points: from `from` offset along from_n to `to` offset
// along to_n (each normal facing the other point's side), aimed at the offset target itself
// and stopping just short of it. Aiming along the direction between the un-offset points
// instead misjudges the distance to the target's plane by offset / cos: at grazing angles
// the ray then reached the light it was meant to test visibility of (docs/rendering.md).
inline Ray shadow_ray_between(const Vec3& from, const Vec3& from_n, const Vec3& to,
                              const Vec3& to_n) {
    Ray r;
    r.o = offset_ray_origin(from, from_n);
    const Vec3 d = offset_ray_origin(to, to_n) - r.o;
    const float length = std::sqrt(glm::dot(d, d));
    r.d = length > 0.0f ? d / length : Vec3(0.0f, 0.0f, 1.0f);
    r.tmax = length * (1.0f - 1e-5f);
    return r;
}

inline float safe_sqrt(float x) { return std::sqrt(std::max(0.0f, x)); }
inline float sqr(float x) { return x * x; }

}  // namespace pathfarm
