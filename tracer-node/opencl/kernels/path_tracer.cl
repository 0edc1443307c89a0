// The path-tracing loop (common/render/path_tracer.cpp) and the per-pixel sample loop
// (common/render/frame_render.cpp). PF_FEATURES (SceneFeature bits) is set when the program
// is built: a variant leaves out what its scenes lack, like PathTracer::trace_with<kFeatures>.

#ifndef PF_FEATURES
#define PF_FEATURES 7u
#endif
#define PF_EMITTERS ((PF_FEATURES & PF_FEATURE_EMITTERS) != 0u)
#define PF_ENVIRONMENT ((PF_FEATURES & PF_FEATURE_ENVIRONMENT) != 0u)
#define PF_TRANSMISSION ((PF_FEATURES & PF_FEATURE_TRANSMISSION) != 0u)

#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

bool pf_consistent_side(float3 w_world, float3 w_local, float3 ng) {
    return dot(w_world, ng) * w_local.z > 0.0f;
}

float pf_light_pdf_solid_angle(const PfScene* s, const PfHit* hit, const PfSurface* sp,
                               float3 origin, float3 origin_normal) {
    const float pdf_area = pf_triangle_pdf_area(s, hit->instance, hit->prim, origin, origin_normal);
    if (pdf_area <= 0.0f) return 0.0f;
    const float3 d = sp->p - origin;
    const float dist2 = dot(d, d);
    const float cos_light = fabs(dot(sp->ng, d)) / sqrt(dist2);
    return cos_light > 0.0f ? pdf_area * dist2 / cos_light : 0.0f;
}

// Next-event estimation (common/render/direct_light.cpp): one light sample, or with
// fp->light_candidates > 1 resampled importance sampling over that many candidates.
typedef struct {
    PfLightSample ls;
    float3 wi;
    float dist;
    float3 contribution;  // unshadowed, MIS-weighted, over the light sampler's pdf
} PfLightCandidate;

typedef struct {
    const PfSurface* sp;
    const PfBsdf* bsdf;
    const PfFrame* frame;
    float3 shading_ng, wo_local, sigma_a;
} PfShadingPoint;

bool pf_light_candidate(const PfScene* s, const PfFrameParams* fp, const PfShadingPoint* x,
                        float u_select, float2 u_light, PfLightCandidate* c) {
    const PfSurface* sp = x->sp;
    if (!pf_sample_light(s, sp->p, sp->ng, u_select, u_light, &c->ls) || c->ls.pdf <= 0.0f ||
        pf_max3(c->ls.radiance) <= 0.0f)
        return false;
    float pdf_light = c->ls.pdf;
    c->dist = PF_INFINITY;
    if (c->ls.environment) {
        c->wi = c->ls.p;
    } else {
        const float3 d = c->ls.p - sp->p;
        const float dist2 = dot(d, d);
        c->dist = sqrt(dist2);
        c->wi = d / c->dist;
        const float cos_light = fabs(dot(c->ls.n, c->wi));
        if (cos_light <= 0.0f || dist2 <= 0.0f) return false;
        pdf_light *= dist2 / cos_light;
    }
    const float3 wi_local = pf_to_local(x->frame, c->wi);
    if (!pf_consistent_side(c->wi, wi_local, x->shading_ng)) return false;
    const float3 f = pf_bsdf_eval(x->bsdf, x->wo_local, wi_local) * fabs(wi_local.z);
    if (pf_max3(f) <= 0.0f) return false;
    const float weight =
        fp->strategy == PF_STRATEGY_LIGHT_ONLY
            ? 1.0f
            : pf_power_heuristic(pdf_light, pf_bsdf_pdf(x->bsdf, x->wo_local, wi_local));
    // Beer's law along the shadow segment (direct_light.cpp).
    float3 transmittance = (float3)(1.0f);
    if (PF_TRANSMISSION && !c->ls.environment) {
        const float3 medium = x->bsdf->w_glass <= 0.0f ? x->sigma_a
                              : dot(c->wi, sp->ng) < 0.0f
                                  ? pf_vec3(s->materials[sp->material].sigma_a)
                                  : (float3)(0.0f);
        if (pf_max3(medium) > 0.0f) transmittance = exp(-medium * c->dist);
    }
    c->contribution = f * transmittance * c->ls.radiance * (weight / pdf_light);
    return pf_max3(c->contribution) > 0.0f;
}

bool pf_unoccluded(const PfScene* s, const PfShadingPoint* x, const PfLightCandidate* c,
                   uint* rays) {
    const float3 ng = dot(c->wi, x->sp->ng) > 0.0f ? x->sp->ng : -x->sp->ng;
    PfRay shadow;
    if (c->ls.environment) {
        shadow.o = pf_offset_ray_origin(x->sp->p, ng);
        shadow.d = c->wi;
        shadow.tmax = PF_INFINITY;
    } else {
        const float3 n = c->ls.n;
        shadow = pf_shadow_ray_between(x->sp->p, ng, c->ls.p, dot(n, c->wi) < 0.0f ? n : -n);
    }
    ++*rays;
    PfHit unused;
    return !pf_trace(s, shadow, &unused, true);
}

float pf_wrap_unit(float x) { return fmin(x - floor(x), 0x1.fffffep-1f); }

float3 pf_sample_direct(const PfScene* s, const PfFrameParams* fp, const PfShadingPoint* x,
                        PfSampler* sampler, uint* rays) {
    const float2 u_select = pf_next_2d(sampler);
    const float2 u_light = pf_next_2d(sampler);
    if (fp->strategy == PF_STRATEGY_BSDF_ONLY || pf_lights_empty(s->globals) ||
        !x->bsdf->has_non_delta)
        return (float3)(0.0f);
    const int m = clamp(fp->light_candidates, 1, PF_MAX_LIGHT_CANDIDATES);
    if (m == 1) {
        PfLightCandidate c;
        if (!pf_light_candidate(s, fp, x, u_select.x, u_light, &c) || !pf_unoccluded(s, x, &c, rays))
            return (float3)(0.0f);
        return c.contribution;
    }
    PfLightCandidate candidates[PF_MAX_LIGHT_CANDIDATES];
    float weight[PF_MAX_LIGHT_CANDIDATES];
    float total = 0.0f;
    for (int j = 0; j < m; ++j) {  // the same candidates as direct_light.cpp draws
        const float u_j = pf_wrap_unit(u_select.x + (float)j / (float)m);
        const float2 v_j = (float2)(pf_wrap_unit(u_light.x + (float)j * PF_R2_X),
                                    pf_wrap_unit(u_light.y + (float)j * PF_R2_Y));
        weight[j] = pf_light_candidate(s, fp, x, u_j, v_j, &candidates[j])
                        ? pf_luminance(candidates[j].contribution)
                        : 0.0f;
        total += weight[j];
    }
    if (!(total > 0.0f) || !isfinite(total)) return (float3)(0.0f);
    const float target = u_select.y * total;
    int chosen = -1;
    float below = 0.0f;
    for (int j = 0; j < m; ++j) {
        if (!(weight[j] > 0.0f)) continue;
        chosen = j;
        below += weight[j];
        if (target < below) break;
    }
    if (!pf_unoccluded(s, x, &candidates[chosen], rays)) return (float3)(0.0f);
    return candidates[chosen].contribution * (total / ((float)m * weight[chosen]));
}

// Ray cones for texture level of detail: path_tracer.h's kConeSpread, kConePdfFloor,
// kConeCosFloor.
#define PF_CONE_SPREAD 0.0625f
#define PF_CONE_PDF_FLOOR 0.1f
#define PF_CONE_COS_FLOOR 0.1f

// Radiance along a camera ray; a non-finite estimate is counted and returned as zero.
float3 pf_trace_path(const PfScene* s, const PfFrameParams* fp, PfRay ray, PfSampler* sampler,
                     uint* rays, uint* nonfinite) {
    float3 radiance = (float3)(0.0f);
    float3 beta = (float3)(1.0f);
    float3 sigma_a = (float3)(0.0f);
    bool delta_bounce = true;
    float bsdf_pdf = 0.0f;
    float3 last_point = ray.o;
    float3 last_normal = (float3)(0.0f);  // PathState::last_normal
    float cone_width = 0.0f, cone_spread = 0.0f;  // PathState's ray cone (kConeSpread)
    for (int depth = 0;; ++depth) {
        PfHit hit;
        ++*rays;
        const bool found = pf_trace(s, ray, &hit, false);
        const bool count_emission = delta_bounce || fp->strategy != PF_STRATEGY_LIGHT_ONLY;
        if (!found) {
            if (PF_ENVIRONMENT && s->globals->has_environment && count_emission) {
                const float3 le = pf_environment_radiance(s->globals, ray.d);
                const float w = delta_bounce || fp->strategy == PF_STRATEGY_BSDF_ONLY
                                    ? 1.0f
                                    : pf_power_heuristic(bsdf_pdf, pf_environment_pdf(s->globals, ray.d));
                radiance += beta * le * w;
            }
            break;
        }
        if (PF_TRANSMISSION && pf_max3(sigma_a) > 0.0f) beta *= exp(-sigma_a * hit.t);

        PfSurface sp = pf_surface(s, hit.instance, hit.prim, hit.u, hit.v);
        const float3 wo = -ray.d;
        if (PF_EMITTERS && count_emission) {
            const float3 le = pf_emitted(s, &sp, wo);
            if (pf_max3(le) > 0.0f) {
                const float w = delta_bounce || fp->strategy == PF_STRATEGY_BSDF_ONLY
                                    ? 1.0f
                                    : pf_power_heuristic(bsdf_pdf, pf_light_pdf_solid_angle(s, &hit, &sp, last_point, last_normal));
                radiance += beta * le * w;
            }
        }
        if (depth >= fp->max_depth) break;

        cone_width += cone_spread * hit.t;
        const float cone_cos = fmax(fabs(dot(ray.d, sp.ng)), PF_CONE_COS_FLOOR);
        const PfMaterialPoint mp = pf_material_point(s, &sp, cone_width * cone_width / cone_cos);
        const PfBsdf bsdf = pf_make_bsdf(mp);
        const bool transmissive = bsdf.w_glass > 0.0f;
        // orient(): opaque surfaces are shaded on the side the ray arrives from.
        float3 ng = sp.ng, ns = sp.ns;
        if (!transmissive && dot(wo, ng) < 0.0f) {
            ng = -ng;
            ns = -ns;
        }
        if (!transmissive && dot(wo, ns) <= 0.0f) ns = ng;
        const PfFrame frame = pf_frame_from_normal_tangent(ns, sp.tangent);
        const float3 wo_local = pf_to_local(&frame, wo);
        const PfShadingPoint x = {&sp, &bsdf, &frame, ng, wo_local, sigma_a};
        radiance += beta * pf_sample_direct(s, fp, &x, sampler, rays);

        const float2 u_lobe = pf_next_2d(sampler);
        const float2 u_dir = pf_next_2d(sampler);
        PfBsdfSample bs;
        if (!pf_bsdf_sample(&bsdf, wo_local, u_lobe.x, u_dir, &bs)) break;
        const float3 wi = pf_to_world(&frame, bs.wi);
        if (!pf_consistent_side(wi, bs.wi, ng)) break;
        const float3 ng_out = dot(wi, ng) > 0.0f ? ng : -ng;
        beta *= bs.f * (fabs(bs.wi.z) / bs.pdf);
        delta_bounce = bs.delta;
        bsdf_pdf = bs.pdf;
        if (!bs.delta) cone_spread += PF_CONE_SPREAD / sqrt(fmax(bs.pdf, PF_CONE_PDF_FLOOR));

        if (PF_TRANSMISSION && transmissive && dot(wi, sp.ng) * dot(wo, sp.ng) < 0.0f)
            sigma_a = dot(wi, sp.ng) < 0.0f ? pf_vec3(s->materials[sp.material].sigma_a)
                                            : (float3)(0.0f);

        if (depth + 1 >= fp->rr_start_depth) {
            const float survive = fmin(1.0f, pf_max3(beta) * fp->rr_scale);
            if (u_lobe.y >= survive) break;
            beta /= survive;
        }
        last_point = sp.p;
        last_normal = sp.ng;
        ray.o = pf_offset_ray_origin(sp.p, ng_out);
        ray.d = wi;
        ray.tmax = PF_INFINITY;
    }
    if (!pf_is_finite3(radiance)) {
        ++*nonfinite;
        return (float3)(0.0f);
    }
    return radiance;
}

// What a camera ray shows the denoiser, as FirstHit's 12 words (common/film/first_hits.h):
// distance, instance, shading normal facing the ray, base colour, flags, triangle and
// barycentrics of its first hit, or through mirrors and clear glass of the first surface
// beyond them (PathTracer::first_hit, common/render/first_hit.cpp).
#define PF_SHARP_MAX_ALPHA 0.04f
#define PF_GLOSSY_MAX_ALPHA 0.1f
#define PF_MAX_REPLACED_BOUNCES 3
#define PF_PASS_DIFFUSE 0
#define PF_PASS_MIRROR 1
#define PF_PASS_CLEAR_GLASS 2
#define PF_PASS_SHARP 3
int pf_first_hit_pass(const PfMaterialPoint* mp, bool emits) {
    if (emits) return PF_PASS_SHARP;
    const bool smooth = mp->alpha < PF_SHARP_MAX_ALPHA;
    if (mp->transmission > 0.0f) return smooth ? PF_PASS_CLEAR_GLASS : PF_PASS_SHARP;
    if (mp->metallic >= 0.5f && smooth) return PF_PASS_MIRROR;
    return PF_PASS_DIFFUSE;
}
void pf_write_first_hit(__global float* out, float distance, uint instance, float3 n, float3 albedo,
                        uint flags, uint prim, float u, float v) {
    out[0] = distance;
    out[1] = as_float(instance);
    out[2] = n.x, out[3] = n.y, out[4] = n.z;
    out[5] = albedo.x, out[6] = albedo.y, out[7] = albedo.z;
    out[8] = as_float(flags);
    out[9] = as_float(prim);
    out[10] = u, out[11] = v;
}
void pf_first_hit(const PfScene* s, PfRay ray, __global float* out, uint* rays) {
    PfHit hit;
    ++*rays;
    if (!pf_trace(s, ray, &hit, false)) {
        pf_write_first_hit(out, PF_INFINITY, 0xffffffffu, (float3)(0.0f), (float3)(0.0f), 0u,
                           0xffffffffu, 0.0f, 0.0f);
        return;
    }
    const float3 camera_d = ray.d;
    float travelled = 0.0f;
    float3 tint = (float3)(1.0f);
    float3 mirrors[PF_MAX_REPLACED_BOUNCES];
    int mirrored = 0;
    for (int bounce = 0;; ++bounce) {
        PfSurface sp = pf_surface(s, hit.instance, hit.prim, hit.u, hit.v);
        const PfMaterialPoint mp = pf_material_point(s, &sp, 0.0f);
        const float3 n = dot(sp.ns, ray.d) > 0.0f ? -sp.ns : sp.ns;
        const float3 le = pf_emitted(s, &sp, -ray.d);
        const int pass = pf_first_hit_pass(&mp, fmax(le.x, fmax(le.y, le.z)) > 0.0f);
        travelled += hit.t;
        const uint glossy = mp.alpha < PF_GLOSSY_MAX_ALPHA ? 4u : 0u;
        if (bounce == 0) {
            pf_write_first_hit(out, hit.t, hit.instance, n, mp.base_color,
                               pass == PF_PASS_DIFFUSE ? glossy : 1u, hit.prim, hit.u, hit.v);
            if (pass == PF_PASS_DIFFUSE) return;
        } else if (pass == PF_PASS_DIFFUSE) {
            float3 seen = n;
            for (int k = mirrored - 1; k >= 0; --k)
                seen -= 2.0f * dot(seen, mirrors[k]) * mirrors[k];
            if (dot(seen, camera_d) > 0.0f) seen = -seen;
            pf_write_first_hit(out, travelled, hit.instance, normalize(seen), tint * mp.base_color,
                               2u | glossy, 0xffffffffu, 0.0f, 0.0f);
            return;
        }
        // An emitter, rough glass, the sky or a chain too long: the first hit as written, sharp.
        if (pass == PF_PASS_SHARP || bounce == PF_MAX_REPLACED_BOUNCES) return;
        const float3 wo = -ray.d;
        float3 wi;
        float etap = 1.0f;
        if (!(pass == PF_PASS_CLEAR_GLASS && pf_refract(wo, sp.ns, mp.ior, &etap, &wi))) {
            wi = pf_reflect(wo, n);  // a mirror, or total internal reflection
            mirrors[mirrored++] = n;
        }
        tint *= mp.base_color;
        const float3 ng_out = dot(wi, sp.ng) > 0.0f ? sp.ng : -sp.ng;
        ray.o = pf_offset_ray_origin(sp.p, ng_out);
        ray.d = normalize(wi);
        ray.tmax = PF_INFINITY;
        ++*rays;
        if (!pf_trace(s, ray, &hit, false)) return;
    }
}

// The camera ray through (px, py) in pixels (generate_camera_ray).
PfRay pf_camera_ray(const PfFrameParams* fp, float px, float py) {
    const float* c2w = fp->camera_to_world;
    const float aspect = (float)fp->width / (float)fp->height;
    const float sx = (2.0f * px / (float)fp->width - 1.0f) * fp->tan_half_fov * aspect;
    const float sy = (1.0f - 2.0f * py / (float)fp->height) * fp->tan_half_fov;
    PfRay ray;
    ray.o = (float3)(c2w[3], c2w[7], c2w[11]);
    ray.d = normalize((float3)(c2w[0] * sx + c2w[1] * sy - c2w[2], c2w[4] * sx + c2w[5] * sy - c2w[6],
                               c2w[8] * sx + c2w[9] * sy - c2w[10]));
    ray.tmax = PF_INFINITY;
    return ray;
}

// One work item per pixel of rows [y0, y1): the box-filtered mean of spp samples, and
// extra_samples[pixel] more when fp.extra_samples is set (FrameSpec::extra_samples, these rows
// only). out holds (y1 - y0) rows of width RGB floats; counters holds (rays, non-finite
// samples) per pixel; first_hits, when fp.first_hits is set, the centre ray's first hit (12
// words per pixel).
#define PF_KERNEL_PARAM(name, type) __global const type* name,
#define PF_SCENE_INIT(name, type) name,
__kernel void pf_render_rows(PfFrameParams fp, PF_SCENE_ARRAYS(PF_KERNEL_PARAM)
                                 __global const PfSceneGlobals* globals,
                             __global float* out, __global uint* counters,
                             __global float* first_hits,
                             __global const uchar* extra_samples) {
    const int x = (int)get_global_id(0);
    const int row = (int)get_global_id(1);
    if (x >= fp.width || row >= fp.y1 - fp.y0) return;
    const int y = fp.y0 + row;
    PfScene s = {PF_SCENE_ARRAYS(PF_SCENE_INIT) globals};
    uint rays = 0, nonfinite = 0;
#ifdef cl_khr_fp64
    double3 sum = (double3)(0.0);
#else
    float3 sum = (float3)(0.0f), carry = (float3)(0.0f);  // Kahan summation
#endif
    const size_t o = (size_t)row * (size_t)fp.width + (size_t)x;
    const int spp = max(fp.spp + (fp.extra_samples ? (int)extra_samples[o] : 0), 1);
    for (int k = fp.first_sample; k < fp.first_sample + spp; ++k) {
        PfSampler sampler =
            pf_make_sampler((uint)x, (uint)y, fp.frame, (uint)k, fp.seed, globals->sobol_dim1);
        const float2 jitter = pf_next_2d(&sampler);
        const PfRay ray = pf_camera_ray(&fp, (float)x + jitter.x, (float)y + jitter.y);
        const float3 l = pf_trace_path(&s, &fp, ray, &sampler, &rays, &nonfinite);
#ifdef cl_khr_fp64
        sum += convert_double3(l);
#else
        const float3 yk = l - carry;
        const float3 t = sum + yk;
        carry = (t - sum) - yk;
        sum = t;
#endif
    }
    if (fp.first_hits)
        pf_first_hit(&s, pf_camera_ray(&fp, (float)x + 0.5f, (float)y + 0.5f), first_hits + 12 * o,
                     &rays);
#ifdef cl_khr_fp64
    const double inv_spp = 1.0 / (double)spp;
    out[3 * o + 0] = (float)(sum.x * inv_spp);
    out[3 * o + 1] = (float)(sum.y * inv_spp);
    out[3 * o + 2] = (float)(sum.z * inv_spp);
#else
    out[3 * o + 0] = sum.x / (float)spp;
    out[3 * o + 1] = sum.y / (float)spp;
    out[3 * o + 2] = sum.z / (float)spp;
#endif
    counters[2 * o] = rays;
    counters[2 * o + 1] = nonfinite;
}
