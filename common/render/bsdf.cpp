// Evaluation, density and sampling of the glTF BSDF (see bsdf.h for the model).
#include "common/render/bsdf.h"

#include "common/render/fresnel.h"
#include "common/render/ggx.h"
#include "common/sampling/sampling.h"

namespace pathfarm {
namespace {

bool same_hemisphere(const Vec3& a, const Vec3& b) { return a.z * b.z > 0.0f; }
Vec3 mirror_z(const Vec3& w) { return {-w.x, -w.y, w.z}; }

}  // namespace

Bsdf::Bsdf(const MaterialPoint& mp)
    : mp_(mp),
      w_metal_(std::clamp(mp.metallic, 0.0f, 1.0f)),
      w_glass_((1.0f - w_metal_) * std::clamp(mp.transmission, 0.0f, 1.0f)),
      w_plastic_(1.0f - w_metal_ - w_glass_),
      smooth_(mp.alpha < kDeltaAlpha) {
    const float r = (mp.ior - 1.0f) / (mp.ior + 1.0f);
    f0_dielectric_ = glm::min(Rgb(r * r) * mp.specular_color, Rgb(1.0f)) * mp.specular;
    // The Lambert base of the plastic lobe is never a delta lobe.
    has_non_delta_ = !smooth_ || w_plastic_ > 0.0f;
    rough_specular_ = !smooth_ && (w_metal_ > 0.0f || (w_plastic_ > 0.0f && mp.specular > 0.0f));
}

BsdfOutgoing Bsdf::outgoing(const Vec3& wo) const {
    BsdfOutgoing o;
    o.wo = wo;
    if (rough_specular_) o.lambda_o = Ggx(mp_.alpha).lambda(wo);
    o.plastic_specular = plastic_specular_probability(wo);
    o.plastic_transmit_o = plastic_transmittance(wo.z);
    return o;
}

// What the plastic's specular layer lets through at cosine c: all of it without a layer
// (specular 0: F0 and F90 are 0, so Schlick's Fresnel is exactly 0).
float Bsdf::plastic_transmittance(float c) const {
    if (!(mp_.specular > 0.0f)) return 1.0f;
    return 1.0f - max_component(fresnel_schlick(f0_dielectric_, Rgb(mp_.specular), c));
}

void Bsdf::eval_pdf_reflection(const BsdfOutgoing& o, const Vec3& wi, Rgb& f, float& pdf) const {
    const Vec3& wo = o.wo;
    if (wo.z <= 0.0f || wi.z <= 0.0f) return;
    // The microfacet terms the metal and the plastic's specular layer share: the value's
    // D G2 / (4 cos_o cos_i) and the density of the visible normal m. A pure Lambert surface
    // (no metal, specular 0: OBJ's Ks 0) needs none of them.
    float cos_om = 0.0f, specular = 0.0f, visible = 0.0f;
    if (rough_specular_) {
        const Ggx ggx(mp_.alpha);
        const Vec3 m = glm::normalize(wo + wi);
        const float d = ggx.d(m);
        cos_om = glm::dot(wo, m);
        const float g2 = 1.0f / (1.0f + o.lambda_o + ggx.lambda(wi));
        specular = d * g2 / (4.0f * wo.z * wi.z);
        visible = 1.0f / (1.0f + o.lambda_o) / std::abs(wo.z) * d * std::abs(cos_om);
    }
    if (w_metal_ > 0.0f && !smooth_) {
        f += w_metal_ * (fresnel_schlick(mp_.base_color, Rgb(1.0f), cos_om) * specular);
        pdf += w_metal_ * visible / (4.0f * cos_om);
    }
    if (w_plastic_ > 0.0f) {
        // The Lambert base receives what the specular layer transmits on the way in and out.
        // The glTF spec's (1 - F(v.h)) weighting reflects more than it receives at grazing
        // angles; this symmetric form is reciprocal and conserves energy (bsdf_test).
        const float t_i = plastic_transmittance(wi.z);
        Rgb value = (o.plastic_transmit_o * t_i) * mp_.base_color * kInvPi;
        if (!smooth_ && mp_.specular > 0.0f)
            value += fresnel_schlick(f0_dielectric_, Rgb(mp_.specular), cos_om) * specular;
        f += w_plastic_ * value;
        const float ps = o.plastic_specular;  // 0 without a specular layer
        float p = (1.0f - ps) * cosine_hemisphere_pdf(wi.z);
        if (rough_specular_) p += ps * visible / (4.0f * cos_om);
        pdf += w_plastic_ * p;
    }
}

float Bsdf::eval_glass(const Vec3& wo, const Vec3& wi) const {
    if (smooth_ || wo.z == 0.0f || wi.z == 0.0f) return 0.0f;
    const bool reflect_event = same_hemisphere(wo, wi);
    const float etap = reflect_event ? 1.0f : (wo.z > 0.0f ? mp_.ior : 1.0f / mp_.ior);
    Vec3 m = wi * etap + wo;
    if (glm::dot(m, m) == 0.0f) return 0.0f;
    m = glm::normalize(m);
    if (m.z < 0.0f) m = -m;
    if (glm::dot(m, wi) * wi.z < 0.0f || glm::dot(m, wo) * wo.z < 0.0f) return 0.0f;
    const Ggx ggx(mp_.alpha);
    const float fr = fresnel_dielectric(glm::dot(wo, m), mp_.ior);
    if (reflect_event) return ggx.d(m) * ggx.g2(wo, wi) * fr / std::abs(4.0f * wi.z * wo.z);
    const float denom = sqr(glm::dot(wi, m) + glm::dot(wo, m) / etap) * wi.z * wo.z;
    const float ft = ggx.d(m) * (1.0f - fr) * ggx.g2(wo, wi) *
                     std::abs(glm::dot(wi, m) * glm::dot(wo, m) / denom);
    return ft / (etap * etap);  // radiance scaling across the interface
}

float Bsdf::pdf_glass(const Vec3& wo, const Vec3& wi) const {
    if (smooth_ || wo.z == 0.0f || wi.z == 0.0f) return 0.0f;
    const bool reflect_event = same_hemisphere(wo, wi);
    const float etap = reflect_event ? 1.0f : (wo.z > 0.0f ? mp_.ior : 1.0f / mp_.ior);
    Vec3 m = wi * etap + wo;
    if (glm::dot(m, m) == 0.0f) return 0.0f;
    m = glm::normalize(m);
    if (m.z < 0.0f) m = -m;
    if (glm::dot(m, wi) * wi.z < 0.0f || glm::dot(m, wo) * wo.z < 0.0f) return 0.0f;
    const Ggx ggx(mp_.alpha);
    const float fr = fresnel_dielectric(glm::dot(wo, m), mp_.ior);
    if (reflect_event) return ggx.visible_d(wo, m) / (4.0f * std::abs(glm::dot(wo, m))) * fr;
    const float denom = sqr(glm::dot(wi, m) + glm::dot(wo, m) / etap);
    return ggx.visible_d(wo, m) * std::abs(glm::dot(wi, m)) / denom * (1.0f - fr);
}

float Bsdf::plastic_specular_probability(const Vec3& wo) const {
    if (mp_.specular <= 0.0f || smooth_) return smooth_ && mp_.specular > 0.0f ? 0.5f : 0.0f;
    const float fs = max_component(fresnel_schlick(f0_dielectric_, Rgb(mp_.specular), wo.z));
    const float diffuse = (1.0f - fs) * luminance(mp_.base_color);
    return std::clamp(fs / std::max(fs + diffuse, 1e-6f), 0.1f, 0.9f);
}

Rgb Bsdf::eval_pdf(const BsdfOutgoing& o, const Vec3& wi, float& pdf) const {
    Rgb f(0.0f);
    pdf = 0.0f;
    eval_pdf_reflection(o, wi, f, pdf);
    if (w_glass_ > 0.0f) {
        f += Rgb(w_glass_ * eval_glass(o.wo, wi));
        pdf += w_glass_ * pdf_glass(o.wo, wi);
    }
    return f;
}

Rgb Bsdf::eval(const Vec3& wo, const Vec3& wi) const {
    float pdf = 0.0f;
    return eval_pdf(outgoing(wo), wi, pdf);
}

float Bsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    float pdf = 0.0f;
    eval_pdf(outgoing(wo), wi, pdf);
    return pdf;
}

bool Bsdf::sample_glass(const Vec3& wo, float u_lobe, Vec2 u, BsdfSample& out) const {
    if (wo.z == 0.0f) return false;
    if (smooth_) {
        const float fr = fresnel_dielectric(wo.z, mp_.ior);
        if (u_lobe < fr) {
            out.wi = mirror_z(wo);
            out.f = Rgb(w_glass_ * fr / std::abs(out.wi.z));
            out.pdf = w_glass_ * fr;
        } else {
            float etap = 1.0f;
            if (!refract(wo, Vec3(0, 0, 1), mp_.ior, etap, out.wi)) return false;
            out.f = Rgb(w_glass_ * (1.0f - fr) / std::abs(out.wi.z) / (etap * etap));
            out.pdf = w_glass_ * (1.0f - fr);
        }
        out.delta = true;
        return true;
    }
    const Vec3 m = Ggx(mp_.alpha).sample_visible_normal(wo, u);
    const float fr = fresnel_dielectric(glm::dot(wo, m), mp_.ior);
    float etap = 1.0f;
    if (u_lobe < fr) {
        out.wi = reflect(wo, m);
        if (!same_hemisphere(wo, out.wi)) return false;
    } else if (!refract(wo, m, mp_.ior, etap, out.wi) || same_hemisphere(wo, out.wi)) {
        return false;
    }
    return true;  // value and density are filled by the caller's full evaluation
}

bool Bsdf::sample(const BsdfOutgoing& o, float u_lobe, Vec2 u, BsdfSample& out) const {
    const Vec3& wo = o.wo;
    out = BsdfSample{};
    if (u_lobe < w_glass_) {
        if (!sample_glass(wo, u_lobe / w_glass_, u, out)) return false;
        if (out.delta) return true;
    } else {
        if (wo.z <= 0.0f) return false;
        u_lobe = (u_lobe - w_glass_) / std::max(1.0f - w_glass_, 1e-7f);
        const bool metal = u_lobe * (w_metal_ + w_plastic_) < w_metal_;
        const float ps = metal ? 1.0f : o.plastic_specular;
        const float u_spec =
            metal ? 0.0f : (u_lobe * (w_metal_ + w_plastic_) - w_metal_) / w_plastic_;
        const bool specular = metal || u_spec < ps;
        if (specular && smooth_) {
            out.wi = mirror_z(wo);
            const Rgb f = metal ? fresnel_schlick(mp_.base_color, Rgb(1.0f), wo.z)
                                : fresnel_schlick(f0_dielectric_, Rgb(mp_.specular), wo.z);
            out.f = (metal ? w_metal_ : w_plastic_) * f / out.wi.z;
            out.pdf = metal ? w_metal_ : w_plastic_ * ps;
            out.delta = true;
            return true;
        }
        out.wi = specular ? reflect(wo, Ggx(mp_.alpha).sample_visible_normal(wo, u))
                          : sample_cosine_hemisphere(u);
        if (out.wi.z <= 0.0f) return false;
    }
    out.f = eval_pdf(o, out.wi, out.pdf);
    return out.pdf > 0.0f;
}

}  // namespace pathfarm
