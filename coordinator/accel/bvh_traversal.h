// CPU traversal of the flat BVH layout: a generic nearest-first walk, and closest / any hit
// against one triangle mesh built on it. The top level (instances) reuses the same walk.
#pragma once

#include "common/math/types.h"
#include "common/scene/bvh.h"

namespace pathfarm::coord {

struct TriangleHit {
    float t = kInfinity;
    uint32_t prim = 0;
    float u = 0.0f, v = 0.0f;  // barycentrics of vertices 1 and 2
};

// Entry distance of a ray into a node's box, or infinity when it misses within tmax. Callers
// test with visits(): tmax itself may be infinite, so "entry > tmax" alone would not cull.
inline float enter_box(const BvhNode& n, const Vec3& o, const Vec3& inv_d, float tmax) {
    float t0 = 0.0f, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
        float ta = (n.lower[a] - o[a]) * inv_d[a];
        float tb = (n.upper[a] - o[a]) * inv_d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = ta > t0 ? ta : t0;  // NaN-safe: a NaN slab leaves t0 / t1 alone
        t1 = tb < t1 ? tb : t1;
    }
    return t0 <= t1 * 1.0000004f ? t0 : kInfinity;  // slack for the rounding of the slabs
}

inline bool visits(float entry, float tmax) { return entry != kInfinity && entry <= tmax; }

// Visits the primitives of every leaf the ray enters, nearer children first. leaf(prim, tmax)
// may shrink tmax (closest hit) and returns true to stop (any hit).
template <typename Leaf>
void walk_bvh(const Bvh& bvh, const Vec3& o, const Vec3& d, float& tmax, Leaf&& leaf) {
    if (bvh.nodes.empty()) return;
    const Vec3 inv_d = Vec3(1.0f) / d;
    uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const uint32_t index = stack[--top];
        const BvhNode& n = bvh.nodes[index];
        if (!visits(enter_box(n, o, inv_d, tmax), tmax)) continue;
        if (n.count > 0) {
            for (uint32_t k = n.first; k < n.first + n.count; ++k)
                if (leaf(bvh.prim_indices[k], tmax)) return;
            continue;
        }
        const uint32_t left = index + 1, right = n.first;
        const float tl = enter_box(bvh.nodes[left], o, inv_d, tmax);
        const float tr = enter_box(bvh.nodes[right], o, inv_d, tmax);
        if (top + 2 > 128) continue;  // builds stop at depth 60
        const bool left_first = tl <= tr;
        const uint32_t far = left_first ? right : left, near = left_first ? left : right;
        if (visits(left_first ? tr : tl, tmax)) stack[top++] = far;
        if (visits(left_first ? tl : tr, tmax)) stack[top++] = near;
    }
}

// Ray-triangle intersection (Möller–Trumbore) on (0, ray.tmax].
bool intersect_triangle(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Ray& ray, float& t,
                        float& u, float& v);

// Closest hit on (0, ray.tmax]; ray.d need not be unit length (t is in units of d).
bool intersect_bvh(const Bvh& bvh, const std::vector<Vec3>& positions,
                   const std::vector<uint32_t>& indices, const Ray& ray, TriangleHit& hit);
bool occluded_bvh(const Bvh& bvh, const std::vector<Vec3>& positions,
                  const std::vector<uint32_t>& indices, const Ray& ray);

}  // namespace pathfarm::coord
