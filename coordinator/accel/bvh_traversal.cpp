// Triangle-level closest and any hit on top of walk_bvh.
#include "coordinator/accel/bvh_traversal.h"

namespace pathfarm::coord {

bool intersect_triangle(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Ray& ray, float& t,
                        float& u, float& v) {
    // Möller–Trumbore in double: game-logic queries and tests compare distances to 1e-5
    // relative, which float loses for grazing rays.
    const DVec3 o(ray.o), d(ray.d), a(p0);
    const DVec3 e1 = DVec3(p1) - a, e2 = DVec3(p2) - a;
    const DVec3 pv = glm::cross(d, e2);
    const double det = glm::dot(e1, pv);
    if (det == 0.0 || !std::isfinite(det)) return false;
    const double inv = 1.0 / det;
    const DVec3 tv = o - a;
    const double uu = glm::dot(tv, pv) * inv;
    if (uu < 0.0 || uu > 1.0) return false;
    const DVec3 qv = glm::cross(tv, e1);
    const double vv = glm::dot(d, qv) * inv;
    if (vv < 0.0 || uu + vv > 1.0) return false;
    const double tt = glm::dot(e2, qv) * inv;
    if (!(tt > 0.0 && tt <= double(ray.tmax))) return false;
    t = float(tt);
    u = float(uu);
    v = float(vv);
    return t > 0.0f;
}

bool intersect_bvh(const Bvh& bvh, const std::vector<Vec3>& p, const std::vector<uint32_t>& idx,
                   const Ray& ray, TriangleHit& hit) {
    bool found = false;
    float tmax = ray.tmax;
    walk_bvh(bvh, ray.o, ray.d, tmax, [&](uint32_t tri, float& limit) {
        float t, u, v;
        if (intersect_triangle(p[idx[3 * tri]], p[idx[3 * tri + 1]], p[idx[3 * tri + 2]],
                               Ray{ray.o, ray.d, limit}, t, u, v)) {
            limit = t;
            hit = TriangleHit{t, tri, u, v};
            found = true;
        }
        return false;
    });
    return found;
}

bool occluded_bvh(const Bvh& bvh, const std::vector<Vec3>& p, const std::vector<uint32_t>& idx,
                  const Ray& ray) {
    bool found = false;
    float tmax = ray.tmax;
    walk_bvh(bvh, ray.o, ray.d, tmax, [&](uint32_t tri, float& limit) {
        float t, u, v;
        found = intersect_triangle(p[idx[3 * tri]], p[idx[3 * tri + 1]], p[idx[3 * tri + 2]],
                                   Ray{ray.o, ray.d, limit}, t, u, v);
        return found;
    });
    return found;
}

}  // namespace pathfarm::coord
