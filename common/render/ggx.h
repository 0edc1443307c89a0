// Isotropic GGX (Trowbridge–Reitz) microfacet distribution in a local frame (+Z = normal):
// height-correlated Smith masking, and sampling of the visible normals (Heitz 2018).
#pragma once

#include "common/math/float_util.h"
#include "common/math/types.h"

namespace pathfarm {

class Ggx {
public:
    // alpha = perceptual roughness squared (glTF).
    explicit Ggx(float alpha) : alpha_(std::max(alpha, 1e-4f)) {}

    float alpha() const { return alpha_; }

    float d(const Vec3& m) const {
        if (m.z <= 0.0f) return 0.0f;
        const float a2 = alpha_ * alpha_;
        const float t = m.z * m.z * (a2 - 1.0f) + 1.0f;
        return a2 / (kPi * t * t);
    }
    float lambda(const Vec3& w) const {
        const float cos2 = w.z * w.z;
        if (cos2 <= 0.0f) return 0.0f;
        const float tan2 = std::max(0.0f, 1.0f - cos2) / cos2;
        return 0.5f * (std::sqrt(1.0f + alpha_ * alpha_ * tan2) - 1.0f);
    }
    float g1(const Vec3& w) const { return 1.0f / (1.0f + lambda(w)); }
    float g2(const Vec3& wo, const Vec3& wi) const {
        return 1.0f / (1.0f + lambda(wo) + lambda(wi));
    }

    // Density of visible normals m seen from w (w on either side; uses |w.z|).
    float visible_d(const Vec3& w, const Vec3& m) const {
        const float cos_o = std::abs(w.z);
        if (cos_o == 0.0f) return 0.0f;
        return g1(w) / cos_o * d(m) * std::abs(glm::dot(w, m));
    }

    // Samples a visible normal (upper hemisphere) for w; w below the surface is mirrored up.
    Vec3 sample_visible_normal(Vec3 w, Vec2 u) const {
        if (w.z < 0.0f) w = -w;
        const Vec3 vh = glm::normalize(Vec3(alpha_ * w.x, alpha_ * w.y, w.z));
        const float len2 = vh.x * vh.x + vh.y * vh.y;
        const Vec3 t1 = len2 > 0.0f ? Vec3(-vh.y, vh.x, 0.0f) / std::sqrt(len2) : Vec3(1, 0, 0);
        const Vec3 t2 = glm::cross(vh, t1);
        const float r = std::sqrt(u.x);
        const float phi = 2.0f * kPi * u.y;
        const float p1 = r * std::cos(phi);
        const float s = 0.5f * (1.0f + vh.z);
        const float p2 = (1.0f - s) * safe_sqrt(1.0f - p1 * p1) + s * r * std::sin(phi);
        const Vec3 nh = p1 * t1 + p2 * t2 + safe_sqrt(1.0f - p1 * p1 - p2 * p2) * vh;
        return glm::normalize(Vec3(alpha_ * nh.x, alpha_ * nh.y, std::max(1e-6f, nh.z)));
    }

private:
    float alpha_;
};

}  // namespace pathfarm
