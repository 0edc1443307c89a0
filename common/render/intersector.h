// The one interface between the integrator and a ray-tracing kernel (Embree today). Hits
// report (instance, primitive, barycentrics); the integrator rebuilds the surface from the
// SceneModel, so every backend shades identically.
#pragma once

#include <cstdint>

#include "common/math/types.h"

namespace pathfarm {

struct Hit {
    float t = kInfinity;
    uint32_t instance = 0;  // index into SceneModel::instances
    uint32_t prim = 0;      // triangle index within the instance's mesh
    float u = 0.0f;         // barycentrics: p = (1-u-v) p0 + u p1 + v p2
    float v = 0.0f;
};

class Intersector {
public:
    virtual ~Intersector() = default;
    // Closest hit on [0, ray.tmax]; ray.d must be unit length.
    virtual bool intersect(const Ray& ray, Hit& hit) const = 0;
    // Whether anything lies on [0, ray.tmax].
    virtual bool occluded(const Ray& ray) const = 0;

    // The most rays intersect_coherent() takes in one call.
    static constexpr int kCoherentWidth = 8;
    // Closest hits of `count` (1 to kCoherentWidth) rays that leave from about one point in
    // about one direction, such as neighbouring pixels' camera rays: found[i] and hits[i] are
    // what intersect() answers for rays[i]. A kernel may trace them as one packet (whose
    // traversal shares the nodes they all visit); this one traces them in turn.
    virtual void intersect_coherent(const Ray* rays, int count, Hit* hits, bool* found) const {
        for (int i = 0; i < count; ++i)
            found[i] = intersect(rays[i], hits[i]);
    }
};

}  // namespace pathfarm
