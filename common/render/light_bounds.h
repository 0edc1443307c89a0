// What a light tree knows of a group of emissive triangles (Conty Estevez & Kulla 2018, as in
// pbrt-v4's LightBounds): where they are (a box), which way they face (a cone of normals), how
// much they emit (power) and whether they emit on both sides. Every emitter here is a diffuse
// area light, so light leaves each within 90 degrees of its normal (the paper's theta_e is
// pi/2 throughout and is not stored).
//
// importance() bounds, up to a constant, the light a receiver at p with normal n gets from the
// group: power over squared distance, times the cosine of the smallest angle any emitter in
// the group can make with the direction to p, times the receiver's best cosine. It is zero only
// where no emitter in the group can light p, which keeps next-event estimation unbiased.
//
// estimate() guesses the light itself instead: the group's power-weighted mean cosine towards p
// (exact for one-sided emitters that all face p), plus what that mean cannot say, on average
// over directions: half the two-sided power (unless the group is one emitter: then |cos|) and
// a quarter of the one-sided power whose normals cancel in the mean (a ring of emitters facing
// out has a mean normal near zero, yet lights everything around it), the receiver's cosine
// towards the group's centre, the squared distance
// to that centre (held above a quarter of the bounding radius squared). Where receivers sit
// among large groups (a room lined with lights), the bound says little more than "power over
// radius squared": the ceiling above a floor point and the walls beside it look alike to it,
// while the estimate sees that the walls' emitters face sideways (docs/rendering.md, "Lights").
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "common/math/types.h"

namespace pathfarm {

struct LightBounds {
    Bounds3f box;
    Vec3 axis{0.0f, 0.0f, 1.0f};  // unit cone axis
    float cos_theta_o = 1.0f;     // every normal lies within this angle of the axis
    float power = 0.0f;
    bool two_sided = false;
    // What the group emits on average, for estimate() (the bound above says only what it could
    // emit at most): the sum over its one-sided emitters of power x normal, and the power of
    // its two-sided ones.
    Vec3 power_normal{0.0f};
    float two_sided_power = 0.0f;
};

// The normal cone of two groups (the smallest cone around both, or the whole sphere).
void union_cone(const Vec3& axis_a, float cos_a, const Vec3& axis_b, float cos_b, Vec3& axis,
                float& cos_out);
LightBounds union_bounds(const LightBounds& a, const LightBounds& b);

// What importance() reads of a LightBounds, precomputed and laid out for the hot loop (the
// OpenCL kernel's PfLightNode holds the same words): the bounding sphere of the box, the cone
// with its sine, the power.
struct PackedLightBounds {
    float center[3], radius2;
    float axis[3], cos_theta_o;
    float sin_theta_o, power;
    uint32_t flags;        // kPackedTwoSided; the other bits are the container's (LightTree)
    float mean_normal[3];  // power_normal / power
    // The share of the power, on average over directions, that mean_normal does not account
    // for: half of the two-sided emitters' (they light both sides) and a quarter of the
    // one-sided power whose normals cancel in the mean, 1 - |mean_normal| of it (the mean of
    // max(0, cos) over the sphere): estimate() adds it in every direction.
    float diffuse_share;
};
inline constexpr uint32_t kPackedTwoSided = 1;
PackedLightBounds pack(const LightBounds& b);

namespace detail {
inline float safe_sqrt(float x) { return std::sqrt(std::max(0.0f, x)); }
// cos(max(0, a - b)) from the cosines and sines of a and b, both in [0, pi].
inline float cos_subtract_clamped(float cos_a, float sin_a, float cos_b, float sin_b) {
    return cos_a >= cos_b ? 1.0f : cos_a * cos_b + sin_a * sin_b;
}
}  // namespace detail

// The importance bound itself, inline: a light tree evaluates it twice per level. n: the
// receiver's normal; zero for none (then no receiver cosine is applied).
inline float importance(const PackedLightBounds& b, const Vec3& p, const Vec3& n) {
    using detail::cos_subtract_clamped, detail::safe_sqrt;
    if (!(b.power > 0.0f)) return 0.0f;
    const Vec3 to_p(p.x - b.center[0], p.y - b.center[1], p.z - b.center[2]);
    const float dist2 = glm::dot(to_p, to_p);
    const float inv_dist = dist2 > 0.0f ? 1.0f / std::sqrt(dist2) : 0.0f;
    // The bounding sphere seen from p: half-angle theta_b (everything when p is inside).
    float cos_b = -1.0f, sin_b = 0.0f;
    if (dist2 > b.radius2) {
        const float sin2 = b.radius2 * inv_dist * inv_dist;
        sin_b = std::sqrt(sin2);
        cos_b = safe_sqrt(1.0f - sin2);
    }
    float cos_w = (b.axis[0] * to_p.x + b.axis[1] * to_p.y + b.axis[2] * to_p.z) * inv_dist;
    if (b.flags & kPackedTwoSided) cos_w = std::abs(cos_w);
    // The smallest angle between an emitter's normal and the direction to p:
    // max(0, theta_w - theta_o - theta_b); no light beyond 90 degrees of it.
    float cos_wo = 1.0f, sin_wo = 0.0f;
    if (cos_w < b.cos_theta_o) {
        const float sin_w = safe_sqrt(1.0f - cos_w * cos_w);
        cos_wo = cos_w * b.cos_theta_o + sin_w * b.sin_theta_o;
        sin_wo = std::max(0.0f, sin_w * b.cos_theta_o - cos_w * b.sin_theta_o);
    }
    const float cos_x = cos_subtract_clamped(cos_wo, sin_wo, cos_b, sin_b);
    if (!(cos_x > 0.0f)) return 0.0f;
    float result = b.power * cos_x / std::max({dist2, 0.25f * b.radius2, 1e-20f});
    if (n.x != 0.0f || n.y != 0.0f || n.z != 0.0f) {  // the receiver's best cosine
        const float cos_i = std::abs(glm::dot(to_p, n)) * inv_dist;
        if (cos_i < cos_b) result *= cos_i * cos_b + safe_sqrt(1.0f - cos_i * cos_i) * sin_b;
    }
    return std::isfinite(result) ? result : 0.0f;
}

// The estimate (see above), inline like importance(); its callers zero it where importance()
// is zero (they have that at hand). `single`: the bounds are one emitter's (a two-sided one
// then emits |cos| exactly, twice its diffuse share of one half times |cos|).
inline float estimate(const PackedLightBounds& b, const Vec3& p, const Vec3& n, bool single) {
    const Vec3 to_p(p.x - b.center[0], p.y - b.center[1], p.z - b.center[2]);
    const float dist2 = glm::dot(to_p, to_p);
    const float inv_dist = dist2 > 0.0f ? 1.0f / std::sqrt(dist2) : 0.0f;
    const float one_sided =
        (b.mean_normal[0] * to_p.x + b.mean_normal[1] * to_p.y + b.mean_normal[2] * to_p.z) *
        inv_dist;
    const float spread =
        single ? 2.0f * std::abs(b.axis[0] * to_p.x + b.axis[1] * to_p.y + b.axis[2] * to_p.z) *
                     inv_dist
               : 1.0f;
    float result = b.power * (std::max(0.0f, one_sided) + b.diffuse_share * spread) /
                   std::max({dist2, 0.25f * b.radius2, 1e-20f});
    if (n.x != 0.0f || n.y != 0.0f || n.z != 0.0f) result *= std::abs(glm::dot(to_p, n)) * inv_dist;
    return std::isfinite(result) ? result : 0.0f;
}

// The bounds of one emissive triangle: vertices in world space, `front` the unit normal on its
// emitting side.
LightBounds triangle_light_bounds(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& front,
                                  float power, bool two_sided);

}  // namespace pathfarm
