// Unidirectional path tracer: next-event estimation and BSDF sampling combined by multiple
// importance sampling (power heuristic), Russian roulette, Beer absorption inside dielectrics.
// One call traces one camera sample; all randomness comes from the PixelSampler
// (docs/determinism.md), so any row split or thread count gives the same image.
#pragma once

#include <cstdint>

#include "common/film/first_hits.h"
#include "common/render/intersector.h"
#include "common/render/light_sampler.h"
#include "common/render/shading_scene.h"
#include "common/sampling/rng.h"

namespace pathfarm {

// Which estimators contribute direct light. mis is the renderer; the others exist so tests can
// check that all three converge to the same image.
enum class LightStrategy : uint8_t { mis, light_only, bsdf_only };

struct IntegratorSettings {
    int max_depth = 8;  // maximum number of scattering events; 0 renders emitters only
    LightStrategy strategy = LightStrategy::mis;
    int rr_start_depth = 3;  // Russian roulette from this bounce on
    // Scales the survival probability (<= 1: shorter paths, more noise, still unbiased): the
    // coordinator's workload scaling lowers it when spp is already at its floor.
    float rr_scale = 1.0f;
    // Use the path-tracing loop specialised for the scene's features (feature_mask below);
    // false: the generic loop that handles every feature. Both give the same image bit for bit.
    bool specialise = true;
    // Do not sample emitters a closed opaque surface separates from the camera
    // (SealedEmitters); false samples every emitter, for measuring what culling saves.
    bool cull_sealed_lights = true;
    // How next-event estimation chooses an emissive triangle (docs/rendering.md, "Lights"): by
    // default the tree or power, whichever the scene state needs (LightSampler resolves
    // automatic; measured: bench/scene_ray_cost.py, bench/light_tree_bench.py).
    LightSelection light_selection = LightSelection::automatic;
    // Resampled light selection (RIS, direct_light.cpp): next-event estimation draws this many
    // candidates and traces a shadow ray to one, chosen by its unshadowed contribution; 1: off.
    int light_candidates = 1;
};
inline constexpr int kMaxLightCandidates = 16;
// How RIS shifts candidate j's point on its emitter: j steps of the R2 low-discrepancy
// sequence (Roberts 2018; 1/g and 1/g^2 for g the plastic number).
inline constexpr float kCandidateStepX = 0.75487766624669276f,
                       kCandidateStepY = 0.56984029099805327f;

namespace detail {
// A direction is consistent when the shading and geometric normals agree on which side of
// the surface it leaves to; otherwise light would leak through the mesh.
inline bool consistent_side(const Vec3& w_world, const Vec3& w_local, const Vec3& ng) {
    return glm::dot(w_world, ng) * w_local.z > 0.0f;
}
}  // namespace detail

// What a scene needs of the path-tracing loop. A loop instantiated without a feature leaves
// out its work per bounce (docs/performance.md: the measured benefit).
enum SceneFeature : uint32_t {
    kFeatureEmitters = 1,      // emissive materials: emission at hits, MIS against NEE
    kFeatureEnvironment = 2,   // sun/sky: radiance and MIS for escaping rays
    kFeatureTransmission = 4,  // transmissive materials: Beer absorption inside them
    kAllFeatures = 7,
};

struct SampleCounters {
    uint64_t camera_samples = 0;
    uint64_t rays = 0;               // closest-hit and shadow rays
    uint64_t nonfinite_samples = 0;  // samples discarded because they were NaN/Inf
    void add(const SampleCounters& o) {
        camera_samples += o.camera_samples;
        rays += o.rays;
        nonfinite_samples += o.nonfinite_samples;
    }
};

// GGX alpha below which a metal's first hit is a mirror the denoiser keeps sharp (roughness
// 0.2); the OpenCL kernel's PF_SHARP_MAX_ALPHA is the same.
inline constexpr float kSharpMaxAlpha = 0.04f;
// GGX alpha below which a first hit that is not sharp is glossy (FirstHit::kGlossy: roughness
// about 0.32; builtin:default's marble and gold); the OpenCL kernel's PF_GLOSSY_MAX_ALPHA.
inline constexpr float kGlossyMaxAlpha = 0.1f;
// Mirrors and clear glass a centre ray passes through before the surface it shows replaces
// the first hit (PathTracer::first_hit); the OpenCL kernel's PF_MAX_REPLACED_BOUNCES is the same.
inline constexpr int kMaxReplacedBounces = 3;

// Ray cones for texture level of detail (texture_mips.h): after a non-delta bounce a path's
// cone widens by kConeSpread / sqrt(pdf) radians, the sampled direction's density floored at
// kConePdfFloor; its footprint at the next hit is width^2 / |cos| (cos floored at
// kConeCosFloor). The OpenCL kernel's PF_CONE_* are the same.
inline constexpr float kConeSpread = 1.0f / 16.0f;
inline constexpr float kConePdfFloor = 0.1f;
inline constexpr float kConeCosFloor = 0.1f;

class PathTracer {
public:
    PathTracer(const ShadingScene& shading, const LightSampler& lights, const Intersector& kernel,
               const IntegratorSettings& settings);

    // A camera ray's closest hit, found beforehand (a packet of neighbouring pixels' rays:
    // Intersector::intersect_coherent, which the frame loop calls through kernel()).
    struct KnownHit {
        bool found = false;
        Hit hit;
    };
    // Radiance along a camera ray whose closest hit is `first`. A non-finite estimate is
    // counted and returned as zero.
    Rgb trace(const Ray& ray, const KnownHit& first, PixelSampler& sampler,
              SampleCounters& counters) const {
        return (this->*trace_)(ray, first, sampler, counters);
    }
    // What `ray`, whose closest hit is `first`, meets first: its distance, instance, shading
    // normal facing the ray (as the normal map bends it), base colour and whether a denoiser
    // must keep it sharp (an emitter, transmission, or metal smoother than kSharpMaxAlpha).
    // Through a mirror-like metal or clear glass (up to kMaxReplacedBounces of them) it is the
    // first other surface beyond them instead (FirstHit::kReplaced); where the chain ends at an
    // emitter, rough glass or the sky, the first hit, sharp. A surface shown that is not sharp
    // and smoother than kGlossyMaxAlpha is flagged glossy. Counted as one closest-hit ray,
    // plus one for each ray followed beyond.
    FirstHit first_hit(const Ray& ray, const KnownHit& first, SampleCounters& counters) const;
    uint32_t features() const { return features_; }  // of the loop in use
    const Intersector& kernel() const { return kernel_; }

private:
    using TraceFn = Rgb (PathTracer::*)(Ray, const KnownHit&, PixelSampler&, SampleCounters&) const;
    template <uint32_t kFeatures>
    Rgb trace_with(Ray ray, const KnownHit& first, PixelSampler& sampler,
                   SampleCounters& counters) const;

    // Where next-event estimation happens: sigma_a is the absorption of the medium the path
    // is in, shading_ng the geometric normal on the side being shaded.
    struct ShadingPoint {
        const SurfacePoint& sp;
        const Bsdf& bsdf;
        const struct Frame& frame;
        Vec3 shading_ng;
        const BsdfOutgoing& wo;  // the direction back along the ray, in the shading frame
        Rgb sigma_a;
    };
    // One light sample's contribution at x, or (light_candidates > 1) one chosen from several.
    Rgb sample_direct(const ShadingPoint& x, PixelSampler& sampler, SampleCounters& counters) const;
    struct LightCandidate;
    // With defer_environment, a sun/sky candidate's contribution is left to the caller
    // (LightCandidate::throughput, weight_over_pdf): RIS weighs candidates by it, one sample
    // needs it only where its shadow ray escapes.
    bool light_candidate(const ShadingPoint& x, float u_select, Vec2 u_light, LightCandidate& c,
                         bool defer_environment = false) const;
    bool unoccluded(const ShadingPoint& x, const LightCandidate& c, SampleCounters& counters) const;
    // Density (solid angle, from origin) of light sampling choosing the emitter point sp.
    float light_pdf_solid_angle(const Hit& hit, const Vec3& origin, const Vec3& origin_normal,
                                const SurfacePoint& sp) const;
    struct PathState;
    Rgb escaped(const PathState& s, const Vec3& d) const;
    Rgb emission_at(const PathState& s, const Hit& hit, const SurfacePoint& sp,
                    const Vec3& wo) const;
    template <bool kTransmission>
    bool scatter(PathState& s, Ray& ray, SurfacePoint& sp, int depth, PixelSampler& sampler,
                 SampleCounters& counters) const;

    const ShadingScene& shading_;
    const LightSampler& lights_;
    const Intersector& kernel_;
    IntegratorSettings settings_;
    uint32_t features_ = kAllFeatures;
    TraceFn trace_ = nullptr;
};

// The features `shading`'s scene and `lights` need.
uint32_t scene_features(const ShadingScene& shading, const LightSampler& lights);

}  // namespace pathfarm
