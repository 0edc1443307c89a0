// The glTF BSDF (common/render/bsdf.cpp, ggx.h, fresnel.h and the warps of sampling.h) on the
// device: the same lobes, weights, densities and sampling decisions.

#define PF_DELTA_ALPHA 1e-3f

// ---- sampling.h ----
float2 pf_sample_concentric_disk(float2 u) {
    const float2 o = 2.0f * u - (float2)(1.0f);
    if (o.x == 0.0f && o.y == 0.0f) return (float2)(0.0f);
    float r, theta;
    if (fabs(o.x) > fabs(o.y)) {
        r = o.x;
        theta = (PF_PI / 4.0f) * (o.y / o.x);
    } else {
        r = o.y;
        theta = (PF_PI / 2.0f) - (PF_PI / 4.0f) * (o.x / o.y);
    }
    return r * (float2)(cos(theta), sin(theta));
}
float3 pf_sample_cosine_hemisphere(float2 u) {
    const float2 d = pf_sample_concentric_disk(u);
    return (float3)(d.x, d.y, pf_safe_sqrt(1.0f - d.x * d.x - d.y * d.y));
}
float pf_cosine_hemisphere_pdf(float cos_theta) { return fmax(cos_theta, 0.0f) * PF_INV_PI; }
float3 pf_sample_uniform_sphere(float2 u) {
    const float z = 1.0f - 2.0f * u.x;
    const float r = pf_safe_sqrt(1.0f - z * z);
    const float phi = 2.0f * PF_PI * u.y;
    return (float3)(r * cos(phi), r * sin(phi), z);
}
float3 pf_sample_uniform_cone(float2 u, float cos_max) {
    const float cos_theta = (1.0f - u.x) + u.x * cos_max;
    const float sin_theta = pf_safe_sqrt(1.0f - cos_theta * cos_theta);
    const float phi = 2.0f * PF_PI * u.y;
    return (float3)(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
}
float pf_uniform_cone_pdf(float cos_max) { return 1.0f / (2.0f * PF_PI * (1.0f - cos_max)); }
float2 pf_sample_uniform_triangle(float2 u) {
    const float su = sqrt(u.x);
    return (float2)(u.y * su, 1.0f - su);
}
float pf_power_heuristic(float f_pdf, float g_pdf) {
    const float f = f_pdf * f_pdf, g = g_pdf * g_pdf;
    if (isinf(f)) return 1.0f;
    return f + g > 0.0f ? f / (f + g) : 0.0f;
}

// ---- fresnel.h ----
float pf_fresnel_dielectric(float cos_i, float eta) {
    cos_i = clamp(cos_i, -1.0f, 1.0f);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
    }
    const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;
    const float cos_t = pf_safe_sqrt(1.0f - sin2_t);
    const float r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_parl * r_parl + r_perp * r_perp);
}
float3 pf_fresnel_schlick(float3 f0, float3 f90, float cos_theta) {
    const float m = clamp(1.0f - fabs(cos_theta), 0.0f, 1.0f);
    const float m2 = m * m;
    return f0 + (f90 - f0) * (m2 * m2 * m);
}
bool pf_refract(float3 w, float3 n, float eta, float* etap, float3* wt) {
    float cos_i = dot(n, w);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
        n = -n;
    }
    const float sin2_t = fmax(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return false;
    const float cos_t = pf_safe_sqrt(1.0f - sin2_t);
    *wt = -w / eta + (cos_i / eta - cos_t) * n;
    *etap = eta;
    return true;
}
float3 pf_reflect(float3 w, float3 n) { return -w + 2.0f * dot(w, n) * n; }

// ---- ggx.h ----
float pf_ggx_d(float alpha, float3 m) {
    if (m.z <= 0.0f) return 0.0f;
    const float a2 = alpha * alpha;
    const float t = m.z * m.z * (a2 - 1.0f) + 1.0f;
    return a2 / (PF_PI * t * t);
}
float pf_ggx_lambda(float alpha, float3 w) {
    const float cos2 = w.z * w.z;
    if (cos2 <= 0.0f) return 0.0f;
    const float tan2 = fmax(0.0f, 1.0f - cos2) / cos2;
    return 0.5f * (sqrt(1.0f + alpha * alpha * tan2) - 1.0f);
}
float pf_ggx_g1(float alpha, float3 w) { return 1.0f / (1.0f + pf_ggx_lambda(alpha, w)); }
float pf_ggx_g2(float alpha, float3 wo, float3 wi) {
    return 1.0f / (1.0f + pf_ggx_lambda(alpha, wo) + pf_ggx_lambda(alpha, wi));
}
float pf_ggx_visible_d(float alpha, float3 w, float3 m) {
    const float cos_o = fabs(w.z);
    if (cos_o == 0.0f) return 0.0f;
    return pf_ggx_g1(alpha, w) / cos_o * pf_ggx_d(alpha, m) * fabs(dot(w, m));
}
float3 pf_ggx_sample_visible_normal(float alpha, float3 w, float2 u) {
    if (w.z < 0.0f) w = -w;
    const float3 vh = normalize((float3)(alpha * w.x, alpha * w.y, w.z));
    const float len2 = vh.x * vh.x + vh.y * vh.y;
    const float3 t1 = len2 > 0.0f ? (float3)(-vh.y, vh.x, 0.0f) / sqrt(len2) : (float3)(1, 0, 0);
    const float3 t2 = cross(vh, t1);
    const float r = sqrt(u.x);
    const float phi = 2.0f * PF_PI * u.y;
    const float p1 = r * cos(phi);
    const float sp = 0.5f * (1.0f + vh.z);
    const float p2 = (1.0f - sp) * pf_safe_sqrt(1.0f - p1 * p1) + sp * r * sin(phi);
    const float3 nh = p1 * t1 + p2 * t2 + pf_safe_sqrt(1.0f - p1 * p1 - p2 * p2) * vh;
    return normalize((float3)(alpha * nh.x, alpha * nh.y, fmax(1e-6f, nh.z)));
}

// ---- bsdf.cpp ----
typedef struct {
    PfMaterialPoint mp;
    float alpha;  // Ggx's clamped alpha
    float w_metal, w_glass, w_plastic;
    float3 f0_dielectric;
    bool smooth;
    bool has_non_delta;
} PfBsdf;

typedef struct {
    float3 wi;
    float3 f;
    float pdf;
    bool delta;
} PfBsdfSample;

PfBsdf pf_make_bsdf(PfMaterialPoint mp) {
    PfBsdf b;
    b.mp = mp;
    b.alpha = fmax(mp.alpha, 1e-4f);
    b.w_metal = clamp(mp.metallic, 0.0f, 1.0f);
    b.w_glass = (1.0f - b.w_metal) * clamp(mp.transmission, 0.0f, 1.0f);
    b.w_plastic = 1.0f - b.w_metal - b.w_glass;
    b.smooth = mp.alpha < PF_DELTA_ALPHA;
    const float r = (mp.ior - 1.0f) / (mp.ior + 1.0f);
    b.f0_dielectric = fmin((float3)(r * r) * mp.specular_color, (float3)(1.0f)) * mp.specular;
    b.has_non_delta = !b.smooth || b.w_plastic > 0.0f;
    return b;
}

bool pf_same_hemisphere(float3 a, float3 b) { return a.z * b.z > 0.0f; }
float3 pf_mirror_z(float3 w) { return (float3)(-w.x, -w.y, w.z); }

float3 pf_eval_metal(const PfBsdf* b, float3 wo, float3 wi) {
    if (b->smooth || wo.z <= 0.0f || wi.z <= 0.0f) return (float3)(0.0f);
    const float3 m = normalize(wo + wi);
    const float3 f = pf_fresnel_schlick(b->mp.base_color, (float3)(1.0f), dot(wo, m));
    return f * (pf_ggx_d(b->alpha, m) * pf_ggx_g2(b->alpha, wo, wi) / (4.0f * wo.z * wi.z));
}

float3 pf_eval_plastic(const PfBsdf* b, float3 wo, float3 wi) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return (float3)(0.0f);
    const float3 f0 = b->f0_dielectric, f90 = (float3)(b->mp.specular);
    const float t_o = 1.0f - pf_max3(pf_fresnel_schlick(f0, f90, wo.z));
    const float t_i = 1.0f - pf_max3(pf_fresnel_schlick(f0, f90, wi.z));
    float3 value = (t_o * t_i) * b->mp.base_color * PF_INV_PI;
    if (!b->smooth && b->mp.specular > 0.0f) {
        const float3 m = normalize(wo + wi);
        value += pf_fresnel_schlick(f0, f90, dot(wo, m)) *
                 (pf_ggx_d(b->alpha, m) * pf_ggx_g2(b->alpha, wo, wi) / (4.0f * wo.z * wi.z));
    }
    return value;
}

// Shared by eval_glass and pdf_glass: the generalised half vector, or false when none.
bool pf_glass_half_vector(const PfBsdf* b, float3 wo, float3 wi, float* etap, float3* m_out) {
    const bool reflect_event = pf_same_hemisphere(wo, wi);
    *etap = reflect_event ? 1.0f : (wo.z > 0.0f ? b->mp.ior : 1.0f / b->mp.ior);
    float3 m = wi * *etap + wo;
    if (dot(m, m) == 0.0f) return false;
    m = normalize(m);
    if (m.z < 0.0f) m = -m;
    if (dot(m, wi) * wi.z < 0.0f || dot(m, wo) * wo.z < 0.0f) return false;
    *m_out = m;
    return true;
}

float pf_eval_glass(const PfBsdf* b, float3 wo, float3 wi) {
    if (b->smooth || wo.z == 0.0f || wi.z == 0.0f) return 0.0f;
    float etap;
    float3 m;
    if (!pf_glass_half_vector(b, wo, wi, &etap, &m)) return 0.0f;
    const float fr = pf_fresnel_dielectric(dot(wo, m), b->mp.ior);
    if (pf_same_hemisphere(wo, wi))
        return pf_ggx_d(b->alpha, m) * pf_ggx_g2(b->alpha, wo, wi) * fr / fabs(4.0f * wi.z * wo.z);
    const float denom = pf_sqr(dot(wi, m) + dot(wo, m) / etap) * wi.z * wo.z;
    const float ft = pf_ggx_d(b->alpha, m) * (1.0f - fr) * pf_ggx_g2(b->alpha, wo, wi) *
                     fabs(dot(wi, m) * dot(wo, m) / denom);
    return ft / (etap * etap);
}

float pf_pdf_glass(const PfBsdf* b, float3 wo, float3 wi) {
    if (b->smooth || wo.z == 0.0f || wi.z == 0.0f) return 0.0f;
    float etap;
    float3 m;
    if (!pf_glass_half_vector(b, wo, wi, &etap, &m)) return 0.0f;
    const float fr = pf_fresnel_dielectric(dot(wo, m), b->mp.ior);
    if (pf_same_hemisphere(wo, wi))
        return pf_ggx_visible_d(b->alpha, wo, m) / (4.0f * fabs(dot(wo, m))) * fr;
    const float denom = pf_sqr(dot(wi, m) + dot(wo, m) / etap);
    return pf_ggx_visible_d(b->alpha, wo, m) * fabs(dot(wi, m)) / denom * (1.0f - fr);
}

float pf_plastic_specular_probability(const PfBsdf* b, float3 wo) {
    if (b->mp.specular <= 0.0f || b->smooth)
        return b->smooth && b->mp.specular > 0.0f ? 0.5f : 0.0f;
    const float fs = pf_max3(pf_fresnel_schlick(b->f0_dielectric, (float3)(b->mp.specular), wo.z));
    const float diffuse = (1.0f - fs) * pf_luminance(b->mp.base_color);
    return clamp(fs / fmax(fs + diffuse, 1e-6f), 0.1f, 0.9f);
}

float3 pf_bsdf_eval(const PfBsdf* b, float3 wo, float3 wi) {
    float3 f = (float3)(0.0f);
    if (b->w_metal > 0.0f) f += b->w_metal * pf_eval_metal(b, wo, wi);
    if (b->w_plastic > 0.0f) f += b->w_plastic * pf_eval_plastic(b, wo, wi);
    if (b->w_glass > 0.0f) f += (float3)(b->w_glass * pf_eval_glass(b, wo, wi));
    return f;
}

float pf_bsdf_pdf(const PfBsdf* b, float3 wo, float3 wi) {
    float pdf = 0.0f;
    const bool upper = wo.z > 0.0f && wi.z > 0.0f;
    if (b->w_metal > 0.0f && upper && !b->smooth) {
        const float3 m = normalize(wo + wi);
        pdf += b->w_metal * pf_ggx_visible_d(b->alpha, wo, m) / (4.0f * dot(wo, m));
    }
    if (b->w_plastic > 0.0f && upper) {
        const float ps = pf_plastic_specular_probability(b, wo);
        float p = (1.0f - ps) * pf_cosine_hemisphere_pdf(wi.z);
        if (!b->smooth) {
            const float3 m = normalize(wo + wi);
            p += ps * pf_ggx_visible_d(b->alpha, wo, m) / (4.0f * dot(wo, m));
        }
        pdf += b->w_plastic * p;
    }
    if (b->w_glass > 0.0f) pdf += b->w_glass * pf_pdf_glass(b, wo, wi);
    return pdf;
}

bool pf_sample_glass(const PfBsdf* b, float3 wo, float u_lobe, float2 u, PfBsdfSample* out) {
    if (wo.z == 0.0f) return false;
    if (b->smooth) {
        const float fr = pf_fresnel_dielectric(wo.z, b->mp.ior);
        if (u_lobe < fr) {
            out->wi = pf_mirror_z(wo);
            out->f = (float3)(b->w_glass * fr / fabs(out->wi.z));
            out->pdf = b->w_glass * fr;
        } else {
            float etap = 1.0f;
            float3 wt;
            if (!pf_refract(wo, (float3)(0.0f, 0.0f, 1.0f), b->mp.ior, &etap, &wt)) return false;
            out->wi = wt;
            out->f = (float3)(b->w_glass * (1.0f - fr) / fabs(wt.z) / (etap * etap));
            out->pdf = b->w_glass * (1.0f - fr);
        }
        out->delta = true;
        return true;
    }
    const float3 m = pf_ggx_sample_visible_normal(b->alpha, wo, u);
    const float fr = pf_fresnel_dielectric(dot(wo, m), b->mp.ior);
    float etap = 1.0f;
    if (u_lobe < fr) {
        out->wi = pf_reflect(wo, m);
        if (!pf_same_hemisphere(wo, out->wi)) return false;
    } else {
        float3 wt;
        if (!pf_refract(wo, m, b->mp.ior, &etap, &wt) || pf_same_hemisphere(wo, wt)) return false;
        out->wi = wt;
    }
    return true;
}

bool pf_bsdf_sample(const PfBsdf* b, float3 wo, float u_lobe, float2 u, PfBsdfSample* out) {
    out->wi = (float3)(0.0f);
    out->f = (float3)(0.0f);
    out->pdf = 0.0f;
    out->delta = false;
    if (u_lobe < b->w_glass) {
        if (!pf_sample_glass(b, wo, u_lobe / b->w_glass, u, out)) return false;
        if (out->delta) return true;
    } else {
        if (wo.z <= 0.0f) return false;
        u_lobe = (u_lobe - b->w_glass) / fmax(1.0f - b->w_glass, 1e-7f);
        const bool metal = u_lobe * (b->w_metal + b->w_plastic) < b->w_metal;
        const float ps = metal ? 1.0f : pf_plastic_specular_probability(b, wo);
        const float u_spec =
            metal ? 0.0f : (u_lobe * (b->w_metal + b->w_plastic) - b->w_metal) / b->w_plastic;
        const bool specular = metal || u_spec < ps;
        if (specular && b->smooth) {
            out->wi = pf_mirror_z(wo);
            const float3 f = metal ? pf_fresnel_schlick(b->mp.base_color, (float3)(1.0f), wo.z)
                                   : pf_fresnel_schlick(b->f0_dielectric, (float3)(b->mp.specular), wo.z);
            out->f = (metal ? b->w_metal : b->w_plastic) * f / out->wi.z;
            out->pdf = metal ? b->w_metal : b->w_plastic * ps;
            out->delta = true;
            return true;
        }
        out->wi = specular ? pf_reflect(wo, pf_ggx_sample_visible_normal(b->alpha, wo, u))
                           : pf_sample_cosine_hemisphere(u);
        if (out->wi.z <= 0.0f) return false;
    }
    out->f = pf_bsdf_eval(b, wo, out->wi);
    out->pdf = pf_bsdf_pdf(b, wo, out->wi);
    return out->pdf > 0.0f;
}
