// The path-tracing loop. Conventions: wo points back along the incoming ray, wi is the new
// direction; "ng" is the front-face geometric normal; all MIS weights use solid-angle pdfs.
#include "common/render/path_tracer.h"

#include "common/math/float_util.h"
#include "common/math/frame.h"
#include "common/sampling/sampling.h"

namespace pathfarm {
namespace {

// Shading frame for a hit: opaque surfaces are shaded on the side the ray arrives from;
// transmissive ones keep the outward normal so that "inside" is wo.z < 0.
struct Orientation {
    Vec3 ng;  // geometric normal used for ray offsets and leak checks
    Frame frame;
};

Orientation orient(const SurfacePoint& sp, const Vec3& wo, bool transmissive) {
    Vec3 ng = sp.ng;
    Vec3 ns = sp.ns;
    if (!transmissive && glm::dot(wo, ng) < 0.0f) {
        ng = -ng;
        ns = -ns;
    }
    if (!transmissive && glm::dot(wo, ns) <= 0.0f) ns = ng;
    return {ng, Frame::from_normal_tangent(ns, sp.tangent)};
}

}  // namespace

uint32_t scene_features(const ShadingScene& shading, const LightSampler& lights) {
    uint32_t f = lights.has_environment() ? kFeatureEnvironment : 0u;
    for (const Material& m : shading.model().materials) {
        if (m.is_emissive()) f |= kFeatureEmitters;
        if (m.transmission_factor > 0.0f) f |= kFeatureTransmission;
    }
    return f;
}

PathTracer::PathTracer(const ShadingScene& shading, const LightSampler& lights,
                       const Intersector& kernel, const IntegratorSettings& settings)
    : shading_(shading), lights_(lights), kernel_(kernel), settings_(settings) {
    static constexpr TraceFn kLoops[8] = {&PathTracer::trace_with<0>, &PathTracer::trace_with<1>,
                                          &PathTracer::trace_with<2>, &PathTracer::trace_with<3>,
                                          &PathTracer::trace_with<4>, &PathTracer::trace_with<5>,
                                          &PathTracer::trace_with<6>, &PathTracer::trace_with<7>};
    features_ = settings.specialise ? scene_features(shading, lights) : kAllFeatures;
    trace_ = kLoops[features_];
}

float PathTracer::light_pdf_solid_angle(const Hit& hit, const Vec3& origin,
                                        const Vec3& origin_normal, const SurfacePoint& sp) const {
    const float pdf_area = lights_.triangle_pdf_area(hit.instance, hit.prim, origin, origin_normal);
    if (pdf_area <= 0.0f) return 0.0f;
    const Vec3 d = sp.p - origin;
    const float dist2 = glm::dot(d, d);
    const float cos_light = std::abs(glm::dot(sp.ng, d)) / std::sqrt(dist2);
    return cos_light > 0.0f ? pdf_area * dist2 / cos_light : 0.0f;
}

// What a path carries from one vertex to the next.
struct PathTracer::PathState {
    Rgb radiance{0.0f};
    Rgb beta{1.0f};
    Rgb sigma_a{0.0f};         // absorption of the medium the ray travels in
    bool delta_bounce = true;  // the camera and delta lobes: no MIS partner for emitters
    float bsdf_pdf = 0.0f;
    Vec3 last_point{0.0f};
    Vec3 last_normal{0.0f};  // its geometric normal: the light tree's receiver (light_tree.h)
    // The ray cone (kConeSpread): its width at the last vertex, its spread angle since, and
    // the world-space footprint at the current hit (0 at the camera's: texture level 0).
    float cone_width = 0.0f;
    float cone_spread = 0.0f;
    float footprint = 0.0f;
    // Emission found by BSDF sampling counts unless only light sampling estimates it.
    bool counts_emission(LightStrategy s) const {
        return delta_bounce || s != LightStrategy::light_only;
    }
};

// The sun/sky along an escaping ray, weighted against light sampling.
Rgb PathTracer::escaped(const PathState& s, const Vec3& d) const {
    const Rgb le = lights_.environment_radiance(d);
    const float w = s.delta_bounce || settings_.strategy == LightStrategy::bsdf_only
                        ? 1.0f
                        : power_heuristic(s.bsdf_pdf, lights_.environment_pdf(d));
    return s.beta * le * w;
}

// Emission at a BSDF-sampled hit, weighted against light sampling of the same point.
Rgb PathTracer::emission_at(const PathState& s, const Hit& hit, const SurfacePoint& sp,
                            const Vec3& wo) const {
    const Rgb le = shading_.emitted(sp, wo);
    if (!(max_component(le) > 0.0f)) return Rgb(0.0f);
    const float w = s.delta_bounce || settings_.strategy == LightStrategy::bsdf_only
                        ? 1.0f
                        : power_heuristic(s.bsdf_pdf, light_pdf_solid_angle(hit, s.last_point,
                                                                            s.last_normal, sp));
    return s.beta * le * w;
}

// Next-event estimation at sp, then the BSDF sample that continues the path (its medium and
// Russian roulette included); false when the path ends here.
template <bool kTransmission>
bool PathTracer::scatter(PathState& s, Ray& ray, SurfacePoint& sp, int depth, PixelSampler& sampler,
                         SampleCounters& counters) const {
    const Vec3 wo = -ray.d;
    const MaterialPoint mp = shading_.material_point(sp, s.footprint);
    const Bsdf bsdf(mp);
    const Orientation o = orient(sp, wo, bsdf.transmissive());
    const BsdfOutgoing outgoing = bsdf.outgoing(o.frame.to_local(wo));
    s.radiance +=
        s.beta * sample_direct({sp, bsdf, o.frame, o.ng, outgoing, s.sigma_a}, sampler, counters);

    const Vec2 u_lobe = sampler.next_2d();
    const Vec2 u_dir = sampler.next_2d();
    BsdfSample bs;
    if (!bsdf.sample(outgoing, u_lobe.x, u_dir, bs)) return false;
    const Vec3 wi = o.frame.to_world(bs.wi);
    if (!detail::consistent_side(wi, bs.wi, o.ng)) return false;
    const Vec3 ng_out = glm::dot(wi, o.ng) > 0.0f ? o.ng : -o.ng;
    s.beta *= bs.f * (std::abs(bs.wi.z) / bs.pdf);
    s.delta_bounce = bs.delta;
    s.bsdf_pdf = bs.pdf;
    if (!bs.delta) s.cone_spread += kConeSpread / std::sqrt(std::max(bs.pdf, kConePdfFloor));
    if (kTransmission && bsdf.transmissive() && glm::dot(wi, sp.ng) * glm::dot(wo, sp.ng) < 0.0f)
        s.sigma_a =
            glm::dot(wi, sp.ng) < 0.0f ? shading_.absorption_coefficient(sp.material) : Rgb(0.0f);
    if (depth + 1 >= settings_.rr_start_depth) {
        const float survive = std::min(1.0f, max_component(s.beta) * settings_.rr_scale);
        if (u_lobe.y >= survive) return false;
        s.beta /= survive;
    }
    s.last_point = sp.p;
    s.last_normal = sp.ng;
    ray.o = offset_ray_origin(sp.p, ng_out);
    ray.d = wi;
    ray.tmax = kInfinity;
    return true;
}

template <uint32_t kFeatures>
Rgb PathTracer::trace_with(Ray ray, const KnownHit& first, PixelSampler& sampler,
                           SampleCounters& counters) const {
    constexpr bool kEmitters = kFeatures & kFeatureEmitters;
    constexpr bool kEnvironment = kFeatures & kFeatureEnvironment;
    constexpr bool kTransmission = kFeatures & kFeatureTransmission;
    PathState s;
    s.last_point = ray.o;
    ++counters.camera_samples;
    for (int depth = 0;; ++depth) {
        Hit hit;
        ++counters.rays;
        bool found;
        if (depth == 0) {
            found = first.found;
            hit = first.hit;
        } else {
            found = kernel_.intersect(ray, hit);
        }
        const bool count_emission = s.counts_emission(settings_.strategy);
        if (!found) {
            if (kEnvironment && lights_.has_environment() && count_emission)
                s.radiance += escaped(s, ray.d);
            break;
        }
        if (kTransmission && max_component(s.sigma_a) > 0.0f)
            s.beta *= glm::exp(-s.sigma_a * hit.t);
        SurfacePoint sp = shading_.surface(hit);
        if (kEmitters && count_emission) s.radiance += emission_at(s, hit, sp, -ray.d);
        if (depth >= settings_.max_depth) break;
        s.cone_width += s.cone_spread * hit.t;
        const float cos = std::max(std::abs(glm::dot(ray.d, sp.ng)), kConeCosFloor);
        s.footprint = s.cone_width * s.cone_width / cos;
        if (!scatter<kTransmission>(s, ray, sp, depth, sampler, counters)) break;
    }
    if (!is_finite(s.radiance)) {
        ++counters.nonfinite_samples;
        return Rgb(0.0f);
    }
    return s.radiance;
}

}  // namespace pathfarm
