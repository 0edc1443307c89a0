// The glTF 2.0 BSDF at one surface point, in the local shading frame (+Z = shading normal):
//   metallic * Metal + (1 - metallic) * [transmission * Glass + (1 - transmission) * Plastic]
// Metal: GGX with Schlick Fresnel tinted by the base colour. Plastic: a GGX specular layer
// (KHR_materials_specular, ior) over a Lambert base that receives (1 - F) on the way in and
// out (docs/rendering.md explains the departure from the glTF spec's v.h weighting). Glass: a rough
// or smooth dielectric (Walter et al. 2007) with exact Fresnel. A GGX alpha below kDeltaAlpha is a
// perfect (delta) mirror or interface.
#pragma once

#include "common/math/types.h"

namespace pathfarm {

inline constexpr float kDeltaAlpha = 1e-3f;

// Material parameters at a surface point, textures already applied.
struct MaterialPoint {
    Rgb base_color{0.8f};
    float metallic = 0.0f;
    float alpha = 1.0f;  // GGX alpha = perceptual roughness squared
    float transmission = 0.0f;
    float ior = 1.5f;
    float specular = 1.0f;
    Rgb specular_color{1.0f};
};

struct BsdfSample {
    Vec3 wi{0.0f};
    Rgb f{0.0f};       // BSDF value (no cosine); for delta lobes the value that makes
                       // f * |cos| / pdf the lobe's throughput
    float pdf = 0.0f;  // solid-angle density, or a discrete probability for delta lobes
    bool delta = false;
};

// The terms of every evaluation that depend on the outgoing direction alone: a shading point
// evaluates its BSDF for a light sample and again for its own sample, with the same wo.
struct BsdfOutgoing {
    Vec3 wo{0.0f, 0.0f, 1.0f};
    float lambda_o = 0.0f;          // GGX Smith lambda of wo
    float plastic_specular = 0.0f;  // probability that sampling takes the plastic's specular layer
    float plastic_transmit_o = 1.0f;  // what the plastic's specular layer lets through at wo
};

class Bsdf {
public:
    explicit Bsdf(const MaterialPoint& mp);

    BsdfOutgoing outgoing(const Vec3& wo) const;
    // Non-delta part of the BSDF (no cosine factor) and, in pdf, the density of sample()
    // generating wi through its non-delta lobes: one evaluation shares the half vector, the
    // microfacet density and the masking between the two.
    Rgb eval_pdf(const BsdfOutgoing& o, const Vec3& wi, float& pdf) const;
    Rgb eval(const Vec3& wo, const Vec3& wi) const;
    float pdf(const Vec3& wo, const Vec3& wi) const;
    // u_lobe picks the lobe, u the direction. Returns false when no direction was produced.
    bool sample(const BsdfOutgoing& o, float u_lobe, Vec2 u, BsdfSample& out) const;
    bool sample(const Vec3& wo, float u_lobe, Vec2 u, BsdfSample& out) const {
        return sample(outgoing(wo), u_lobe, u, out);
    }

    // False when every lobe is a delta lobe: light sampling cannot help then.
    bool has_non_delta() const { return has_non_delta_; }
    bool transmissive() const { return w_glass_ > 0.0f; }

private:
    // The metal and plastic lobes (both zero unless wo and wi are above the surface).
    void eval_pdf_reflection(const BsdfOutgoing& o, const Vec3& wi, Rgb& f, float& pdf) const;
    float eval_glass(const Vec3& wo, const Vec3& wi) const;
    float pdf_glass(const Vec3& wo, const Vec3& wi) const;
    float plastic_specular_probability(const Vec3& wo) const;
    float plastic_transmittance(float cos_theta) const;
    bool sample_glass(const Vec3& wo, float u_lobe, Vec2 u, BsdfSample& out) const;

    MaterialPoint mp_;
    float w_metal_, w_glass_, w_plastic_;
    Rgb f0_dielectric_;
    bool smooth_;
    bool has_non_delta_;
    bool rough_specular_;  // a rough metal or specular layer: the microfacet terms are needed
};

}  // namespace pathfarm
