// Vector types (GLM aliases), axis-aligned bounds and rays used across pathfarm.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

namespace pathfarm {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using Mat3 = glm::mat3;
using Mat4 = glm::mat4;
using DVec3 = glm::dvec3;
using DMat4 = glm::dmat4;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 1.0f / kPi;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Linear RGB radiance or reflectance.
using Rgb = glm::vec3;

inline float luminance(const Rgb& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline float max_component(const Vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
inline bool is_finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

struct Bounds3f {
    Vec3 lower{kInfinity};
    Vec3 upper{-kInfinity};

    bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
    void extend(const Vec3& p) {
        lower = glm::min(lower, p);
        upper = glm::max(upper, p);
    }
    void extend(const Bounds3f& b) {
        lower = glm::min(lower, b.lower);
        upper = glm::max(upper, b.upper);
    }
    Vec3 center() const { return 0.5f * (lower + upper); }
    Vec3 extent() const { return upper - lower; }
};

// A ray with origin o and unit direction d; the valid segment is [0, tmax].
struct Ray {
    Vec3 o{0.0f};
    Vec3 d{0.0f, 0.0f, -1.0f};
    float tmax = kInfinity;
};

}  // namespace pathfarm
