// What a pixel's centre ray shows the denoiser (FirstHit): its first hit, or, through mirrors
// and clear glass, the first surface the ray meets beyond them (primary surface replacement,
// as real-time path tracers do for specular surfaces: the reflection is filtered over the
// surface it shows instead of not at all).
#include "common/math/float_util.h"
#include "common/render/fresnel.h"
#include "common/render/path_tracer.h"

namespace pathfarm {
namespace {

// How a first hit's surface passes light on to the denoiser.
enum class Pass { diffuse, mirror, clear_glass, sharp };

Pass pass_of(const MaterialPoint& mp, bool emits) {
    if (emits) return Pass::sharp;
    const bool smooth = mp.alpha < kSharpMaxAlpha;
    if (mp.transmission > 0.0f) return smooth ? Pass::clear_glass : Pass::sharp;
    if (mp.metallic >= 0.5f && smooth) return Pass::mirror;
    return Pass::diffuse;
}

// `v` reflected about the planes through the origin with the unit normals mirrors[0..count),
// the last first: what lies beyond those mirrors as they show it.
Vec3 through_mirrors(Vec3 v, const Vec3* mirrors, int count) {
    for (int k = count - 1; k >= 0; --k)
        v -= 2.0f * glm::dot(v, mirrors[k]) * mirrors[k];
    return v;
}

}  // namespace

FirstHit PathTracer::first_hit(const Ray& ray, const KnownHit& first,
                               SampleCounters& counters) const {
    ++counters.rays;
    if (!first.found) return FirstHit{};
    FirstHit primary;
    Ray r = ray;
    Hit hit = first.hit;
    float travelled = 0.0f;
    Rgb tint(1.0f);
    Vec3 mirrors[kMaxReplacedBounces];  // the normals of the mirrors passed
    int mirrored = 0;
    for (int bounce = 0;; ++bounce) {
        SurfacePoint sp = shading_.surface(hit);
        const MaterialPoint mp = shading_.material_point(sp);
        const Vec3 n = glm::dot(sp.ns, r.d) > 0.0f ? -sp.ns : sp.ns;
        const Pass pass = pass_of(mp, max_component(shading_.emitted(sp, -r.d)) > 0.0f);
        travelled += hit.t;
        const uint32_t glossy = mp.alpha < kGlossyMaxAlpha ? FirstHit::kGlossy : 0u;
        if (bounce == 0)
            primary = {hit.t,
                       hit.instance,
                       n,
                       mp.base_color,
                       pass == Pass::diffuse ? glossy : FirstHit::kSharp,
                       hit.prim,
                       hit.u,
                       hit.v};
        if (pass == Pass::diffuse) {
            if (bounce == 0) return primary;
            // Where the centre ray's path would put it seen straight on: along the camera
            // ray at the distance travelled, its normal reflected by the mirrors passed.
            Vec3 seen = through_mirrors(n, mirrors, mirrored);
            if (glm::dot(seen, ray.d) > 0.0f) seen = -seen;
            return {travelled, hit.instance, glm::normalize(seen), tint * mp.base_color,
                    FirstHit::kReplaced | glossy};
        }
        // An emitter, rough glass, the sky or a chain too long: the pixel stays sharp.
        if (pass == Pass::sharp || bounce == kMaxReplacedBounces) return primary;
        const Vec3 wo = -r.d;
        Vec3 wi;
        float etap = 1.0f;
        if (!(pass == Pass::clear_glass && refract(wo, sp.ns, mp.ior, etap, wi))) {
            wi = reflect(wo, n);  // a mirror, or total internal reflection
            mirrors[mirrored++] = n;
        }
        tint *= mp.base_color;
        const Vec3 ng_out = glm::dot(wi, sp.ng) > 0.0f ? sp.ng : -sp.ng;
        r.o = offset_ray_origin(sp.p, ng_out);
        r.d = glm::normalize(wi);
        r.tmax = kInfinity;
        ++counters.rays;
        if (!kernel_.intersect(r, hit)) return primary;
    }
}

}  // namespace pathfarm
