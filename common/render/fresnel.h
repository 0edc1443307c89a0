// Fresnel reflectance for dielectric interfaces and Schlick's approximation.
#pragma once

#include "common/math/float_util.h"
#include "common/math/types.h"

namespace pathfarm {

// Unpolarised Fresnel reflectance of a dielectric interface. cos_i is measured on the side of
// the incident direction; eta = n_transmitted / n_incident for cos_i > 0 (flipped otherwise).
inline float fresnel_dielectric(float cos_i, float eta) {
    cos_i = std::clamp(cos_i, -1.0f, 1.0f);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
    }
    const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;  // total internal reflection
    const float cos_t = safe_sqrt(1.0f - sin2_t);
    const float r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_parl * r_parl + r_perp * r_perp);
}

inline Rgb fresnel_schlick(const Rgb& f0, const Rgb& f90, float cos_theta) {
    const float m = std::clamp(1.0f - std::abs(cos_theta), 0.0f, 1.0f);
    const float m2 = m * m;
    return f0 + (f90 - f0) * (m2 * m2 * m);
}

// Refracts w (pointing away from the surface) through the interface with normal n. eta is
// n_transmitted / n_incident relative to n's side; returns false on total internal reflection.
// etap receives the relative IOR actually used (1/eta when w is below n).
inline bool refract(const Vec3& w, Vec3 n, float eta, float& etap, Vec3& wt) {
    float cos_i = glm::dot(n, w);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
        n = -n;
    }
    const float sin2_t = std::max(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return false;
    const float cos_t = safe_sqrt(1.0f - sin2_t);
    wt = -w / eta + (cos_i / eta - cos_t) * n;
    etap = eta;
    return true;
}

inline Vec3 reflect(const Vec3& w, const Vec3& n) { return -w + 2.0f * glm::dot(w, n) * n; }

}  // namespace pathfarm
