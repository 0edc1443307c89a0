// Next-event estimation: one light sample per shading point, or resampled importance sampling
// (RIS; Talbot et al. 2005, the Brigade thesis ch. 6.4): several candidates drawn from the light
// sampler, one kept in proportion to its unshadowed contribution, one shadow ray.
//
// The RIS estimator f(y) V(y) / f^(y) * (1/M) sum_j f^(x_j) / p(x_j), with the target f^ the
// luminance of the unshadowed, MIS-weighted contribution, is unbiased for any M as long as each
// candidate alone is distributed by p and f^ > 0 wherever f is: it is, since f = f^ x
// visibility. The candidates share the path's two light numbers: candidate j shifts the
// selection number by j/M (stratified over the emitters) and the point on the emitter by the
// R2 sequence's j-th step, so every candidate is still uniformly distributed and the sampler's
// dimensions stay where they are with RIS on or off. The MIS weights keep the light sampler's
// own pdf of one candidate on both sides (light and BSDF sampling), so they still sum to one.
#include "common/math/float_util.h"
#include "common/math/frame.h"
#include "common/render/path_tracer.h"
#include "common/sampling/sampling.h"

namespace pathfarm {
namespace {

float wrap_unit(float x) { return std::min(x - std::floor(x), kOneBelow); }

}  // namespace

struct PathTracer::LightCandidate {
    LightSample ls;
    Vec3 wi;
    float dist = kInfinity;
    Rgb contribution{0.0f};  // unshadowed, MIS-weighted, over the light sampler's pdf
    // Its factors without the light's radiance, for a sample whose radiance is deferred:
    // contribution = (throughput * radiance) * weight_over_pdf, the same product in order.
    Rgb throughput{0.0f};
    float weight_over_pdf = 0.0f;
};

// One light sample seen from x, before its shadow ray; false when it cannot contribute.
bool PathTracer::light_candidate(const ShadingPoint& x, float u_select, Vec2 u_light,
                                 LightCandidate& c, bool defer_environment) const {
    const auto ls = lights_.sample(x.sp.p, x.sp.ng, u_select, u_light, defer_environment);
    if (!ls || ls->pdf <= 0.0f) return false;
    if (!ls->radiance_deferred && max_component(ls->radiance) <= 0.0f) return false;
    c.ls = *ls;
    float pdf_light = ls->pdf;
    if (ls->environment) {
        c.wi = ls->p;
        c.dist = kInfinity;
    } else {
        const Vec3 d = ls->p - x.sp.p;
        const float dist2 = glm::dot(d, d);
        c.dist = std::sqrt(dist2);
        c.wi = d / c.dist;
        const float cos_light = std::abs(glm::dot(ls->n, c.wi));
        if (cos_light <= 0.0f || dist2 <= 0.0f) return false;
        pdf_light *= dist2 / cos_light;  // area to solid angle
    }
    const Vec3 wi_local = x.frame.to_local(c.wi);
    if (!detail::consistent_side(c.wi, wi_local, x.shading_ng)) return false;
    float bsdf_pdf = 0.0f;
    const Rgb f = x.bsdf.eval_pdf(x.wo, wi_local, bsdf_pdf) * std::abs(wi_local.z);
    if (max_component(f) <= 0.0f) return false;
    const float weight = settings_.strategy == LightStrategy::light_only
                             ? 1.0f
                             : power_heuristic(pdf_light, bsdf_pdf);
    // Beer's law along the shadow segment, as a BSDF-sampled path to the same point gets it:
    // the medium around an opaque vertex, or a dielectric's inside when wi enters it.
    const Rgb medium = !x.bsdf.transmissive() ? x.sigma_a
                       : glm::dot(c.wi, x.sp.ng) < 0.0f
                           ? shading_.absorption_coefficient(x.sp.material)
                           : Rgb(0.0f);
    const Rgb transmittance =
        ls->environment || max_component(medium) <= 0.0f ? Rgb(1.0f) : glm::exp(-medium * c.dist);
    c.throughput = f * transmittance;
    c.weight_over_pdf = weight / pdf_light;
    if (ls->radiance_deferred) return max_component(c.throughput) > 0.0f;
    c.contribution = c.throughput * ls->radiance * c.weight_over_pdf;
    return max_component(c.contribution) > 0.0f;
}

bool PathTracer::unoccluded(const ShadingPoint& x, const LightCandidate& c,
                            SampleCounters& counters) const {
    const Vec3 ng = glm::dot(c.wi, x.sp.ng) > 0.0f ? x.sp.ng : -x.sp.ng;
    Ray shadow;
    if (c.ls.environment) {
        shadow.o = offset_ray_origin(x.sp.p, ng);
        shadow.d = c.wi;
        shadow.tmax = kInfinity;
    } else {
        const Vec3& n = c.ls.n;
        shadow = shadow_ray_between(x.sp.p, ng, c.ls.p, glm::dot(n, c.wi) < 0.0f ? n : -n);
    }
    ++counters.rays;
    return !kernel_.occluded(shadow);
}

Rgb PathTracer::sample_direct(const ShadingPoint& x, PixelSampler& sampler,
                              SampleCounters& counters) const {
    const Vec2 u_select = sampler.next_2d();
    const Vec2 u_light = sampler.next_2d();
    if (settings_.strategy == LightStrategy::bsdf_only || lights_.empty() ||
        !x.bsdf.has_non_delta())
        return Rgb(0.0f);
    const int m = std::clamp(settings_.light_candidates, 1, kMaxLightCandidates);
    if (m == 1) {
        // The sky's radiance only once its shadow ray escapes (indoors most do not).
        LightCandidate c;
        if (!light_candidate(x, u_select.x, u_light, c, true) || !unoccluded(x, c, counters))
            return Rgb(0.0f);
        if (!c.ls.radiance_deferred) return c.contribution;
        return c.throughput * lights_.environment_radiance(c.wi) * c.weight_over_pdf;
    }
    LightCandidate candidates[kMaxLightCandidates];
    float weight[kMaxLightCandidates];
    float total = 0.0f;
    for (int j = 0; j < m; ++j) {
        const float u_j = wrap_unit(u_select.x + float(j) / float(m));
        const Vec2 v_j(wrap_unit(u_light.x + float(j) * kCandidateStepX),
                       wrap_unit(u_light.y + float(j) * kCandidateStepY));
        weight[j] = light_candidate(x, u_j, v_j, candidates[j])
                        ? luminance(candidates[j].contribution)
                        : 0.0f;
        total += weight[j];
    }
    if (!(total > 0.0f) || !std::isfinite(total)) return Rgb(0.0f);
    // The candidate whose share of the total holds u_select.y (a number one sample leaves
    // unused), skipping those of weight zero.
    const float target = u_select.y * total;
    int chosen = -1;
    float below = 0.0f;
    for (int j = 0; j < m; ++j) {
        if (!(weight[j] > 0.0f)) continue;
        chosen = j;
        below += weight[j];
        if (target < below) break;
    }
    const LightCandidate& c = candidates[chosen];
    if (!unoccluded(x, c, counters)) return Rgb(0.0f);
    return c.contribution * (total / (float(m) * weight[chosen]));
}

}  // namespace pathfarm
