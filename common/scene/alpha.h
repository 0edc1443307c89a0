// Alpha coverage (glTF alphaMode) at a surface point: which hits a ray keeps. Both backends
// and the light sampler use these, so every estimator sees the same surfaces.
#pragma once

#include <cstdint>

#include "common/scene/scene_model.h"

namespace pathfarm {

// The base colour's alpha at uv: factor times texture alpha (glTF).
float base_color_alpha(const SceneModel& scene, const Material& m, Vec2 uv);

// Expected fraction of hits kept at alpha: MASK 0 or 1 by the cutoff, BLEND alpha, OPAQUE 1.
float alpha_coverage(const Material& m, float alpha);

// Whether a hit at alpha is kept; u is uniform in [0, 1) and decides BLEND hits (kept when
// u < alpha: stochastic transparency, which is unbiased for any number of layers).
inline bool alpha_keeps_hit(const Material& m, float alpha, float u) {
    switch (m.alpha_mode) {
        case AlphaMode::mask:
            return alpha >= m.alpha_cutoff;
        case AlphaMode::blend:
            return u < alpha;
        case AlphaMode::opaque:
        default:
            return true;
    }
}

// The uniform number for a BLEND decision: a hash of the ray and the candidate hit, so it is
// the same whichever thread, tile or traversal order meets the hit, and however many times
// Embree reports it (spatial splits). The OpenCL kernels compute the same hash.
float alpha_hash(const Vec3& o, const Vec3& d, float t, uint32_t prim);

// The whole test for a hit on triangle `prim` of `mesh` at barycentrics (u, v).
bool alpha_keeps_hit(const SceneModel& scene, const Mesh& mesh, uint32_t prim, float u, float v,
                     const Vec3& o, const Vec3& d, float t);

}  // namespace pathfarm
