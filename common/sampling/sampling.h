// Warping functions from [0,1)^2 to directions and points, with their densities.
// Directions are in a local frame whose +Z is the surface normal; pdfs are per solid angle.
#pragma once

#include "common/math/float_util.h"
#include "common/math/types.h"

namespace pathfarm {

// Shirley–Chiu concentric map of the square onto the unit disk.
inline Vec2 sample_concentric_disk(Vec2 u) {
    const Vec2 o = 2.0f * u - Vec2(1.0f);
    if (o.x == 0.0f && o.y == 0.0f) return Vec2(0.0f);
    float r, theta;
    if (std::abs(o.x) > std::abs(o.y)) {
        r = o.x;
        theta = (kPi / 4.0f) * (o.y / o.x);
    } else {
        r = o.y;
        theta = (kPi / 2.0f) - (kPi / 4.0f) * (o.x / o.y);
    }
    return r * Vec2(std::cos(theta), std::sin(theta));
}

inline Vec3 sample_cosine_hemisphere(Vec2 u) {
    const Vec2 d = sample_concentric_disk(u);
    return {d.x, d.y, safe_sqrt(1.0f - d.x * d.x - d.y * d.y)};
}
inline float cosine_hemisphere_pdf(float cos_theta) { return std::max(cos_theta, 0.0f) * kInvPi; }

inline Vec3 sample_uniform_sphere(Vec2 u) {
    const float z = 1.0f - 2.0f * u.x;
    const float r = safe_sqrt(1.0f - z * z);
    const float phi = 2.0f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline constexpr float kUniformSpherePdf = 1.0f / (4.0f * kPi);

// Uniform directions inside the cone around +Z whose half-angle has cosine cos_max.
inline Vec3 sample_uniform_cone(Vec2 u, float cos_max) {
    const float cos_theta = (1.0f - u.x) + u.x * cos_max;
    const float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
    const float phi = 2.0f * kPi * u.y;
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}
inline float uniform_cone_pdf(float cos_max) { return 1.0f / (2.0f * kPi * (1.0f - cos_max)); }

// Uniform barycentrics (b1, b2) of a triangle; b0 = 1 - b1 - b2. Density 1/area on the triangle.
inline Vec2 sample_uniform_triangle(Vec2 u) {
    const float su = std::sqrt(u.x);
    return {u.y * su, 1.0f - su};
}

// Veach's power heuristic (beta = 2) for MIS between two strategies with nf and ng samples.
inline float power_heuristic(float f_pdf, float g_pdf) {
    const float f = f_pdf * f_pdf;
    const float g = g_pdf * g_pdf;
    if (std::isinf(f)) return 1.0f;
    return f + g > 0.0f ? f / (f + g) : 0.0f;
}

}  // namespace pathfarm
