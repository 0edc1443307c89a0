// Normal cones and the importance bound of a light group (light_bounds.h). The angles are
// handled through their cosines and sines: cos(max(0, a - b)) needs no acos per evaluation.
#include "common/render/light_bounds.h"

#include <algorithm>
#include <cmath>

namespace pathfarm {
namespace {

// Rounding may leave a child's normal a hair outside the union of cones; this much margin
// (radians) keeps every emitter inside its ancestors' cones.
constexpr float kConeMargin = 1e-4f;

float angle_between(const Vec3& a, const Vec3& b) {
    // Stable for nearly equal and nearly opposite directions, unlike acos(dot).
    return glm::dot(a, b) < 0.0f ? kPi - 2.0f * std::asin(std::min(1.0f, glm::length(a + b) / 2))
                                 : 2.0f * std::asin(std::min(1.0f, glm::length(b - a) / 2));
}

// v rotated by `angle` about the unit axis k (Rodrigues).
Vec3 rotate(const Vec3& v, const Vec3& k, float angle) {
    const float c = std::cos(angle), s = std::sin(angle);
    return v * c + glm::cross(k, v) * s + k * glm::dot(k, v) * (1.0f - c);
}

}  // namespace

void union_cone(const Vec3& axis_a, float cos_a, const Vec3& axis_b, float cos_b, Vec3& axis,
                float& cos_out) {
    axis = axis_a;
    cos_out = -1.0f;  // the whole sphere unless something tighter holds
    if (cos_a <= -1.0f || cos_b <= -1.0f) return;
    const float theta_a = std::acos(std::clamp(cos_a, -1.0f, 1.0f));
    const float theta_b = std::acos(std::clamp(cos_b, -1.0f, 1.0f));
    const float theta_d = angle_between(axis_a, axis_b);
    if (std::min(theta_d + theta_b, kPi) <= theta_a) {
        cos_out = cos_a;
        return;
    }
    if (std::min(theta_d + theta_a, kPi) <= theta_b) {
        axis = axis_b;
        cos_out = cos_b;
        return;
    }
    const float theta_o = 0.5f * (theta_a + theta_d + theta_b) + kConeMargin;
    const Vec3 k = glm::cross(axis_a, axis_b);
    const float k_len = glm::length(k);
    if (theta_o >= kPi || !(k_len > 1e-7f)) return;
    axis = glm::normalize(rotate(axis_a, k / k_len, theta_o - kConeMargin - theta_a));
    cos_out = std::cos(theta_o);
}

LightBounds union_bounds(const LightBounds& a, const LightBounds& b) {
    // A dark group lights nothing: it neither widens the box nor the cone (a refit that
    // switches it on recomputes its ancestors).
    if (!(b.power > 0.0f)) return a;
    if (!(a.power > 0.0f)) return b;
    LightBounds u;
    u.box = a.box;
    u.box.extend(b.box);
    union_cone(a.axis, a.cos_theta_o, b.axis, b.cos_theta_o, u.axis, u.cos_theta_o);
    u.power = a.power + b.power;
    u.two_sided = a.two_sided || b.two_sided;
    u.power_normal = a.power_normal + b.power_normal;
    u.two_sided_power = a.two_sided_power + b.two_sided_power;
    return u;
}

PackedLightBounds pack(const LightBounds& b) {
    PackedLightBounds packed{};
    const Vec3 centre = b.box.empty() ? Vec3(0.0f) : b.box.center();
    const Vec3 half = b.box.empty() ? Vec3(0.0f) : 0.5f * b.box.extent();
    for (int k = 0; k < 3; ++k) {
        packed.center[k] = centre[k];
        packed.axis[k] = b.axis[k];
    }
    // A hair larger than the half-diagonal, so rounding never leaves a corner outside.
    packed.radius2 = glm::dot(half, half) * (1.0f + 1e-5f);
    packed.cos_theta_o = b.cos_theta_o;
    packed.sin_theta_o = detail::safe_sqrt(1.0f - b.cos_theta_o * b.cos_theta_o);
    packed.power = b.box.empty() ? 0.0f : b.power;
    packed.flags = b.two_sided ? kPackedTwoSided : 0u;
    const float inv_power = packed.power > 0.0f ? 1.0f / b.power : 0.0f;
    for (int k = 0; k < 3; ++k)
        packed.mean_normal[k] = b.power_normal[k] * inv_power;
    const float two_sided_share = b.two_sided_power * inv_power;
    const float aligned = glm::length(b.power_normal) * inv_power;
    packed.diffuse_share =
        0.5f * two_sided_share + 0.25f * std::max(0.0f, 1.0f - two_sided_share - aligned);
    return packed;
}

LightBounds triangle_light_bounds(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& front,
                                  float power, bool two_sided) {
    LightBounds b;
    b.box.extend(p0);
    b.box.extend(p1);
    b.box.extend(p2);
    const float len = glm::length(front);
    b.axis = len > 0.0f ? front / len : Vec3(0.0f, 0.0f, 1.0f);
    b.cos_theta_o = len > 0.0f ? 1.0f : -1.0f;
    b.power = power;
    b.two_sided = two_sided;
    if (two_sided)
        b.two_sided_power = power;
    else
        b.power_normal = power * b.axis;
    return b;
}

}  // namespace pathfarm
