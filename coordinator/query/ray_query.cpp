// Two-level traversal: instances by the top BVH, then the instance's mesh in object space.
#include "coordinator/query/ray_query.h"

#include "common/math/transform.h"
#include "coordinator/accel/bvh_traversal.h"

namespace pathfarm::coord {
namespace {

template <bool kAnyHit>
bool trace(const AccelSnapshot& accel, const Ray& ray, RayQueryHit* out) {
    bool found = false;
    float tmax = ray.tmax;
    walk_bvh(accel.top, ray.o, ray.d, tmax, [&](uint32_t i, float& limit) {
        const InstanceAccel& inst = accel.instances[i];
        const MeshAccel& mesh = *accel.meshes.at(inst.mesh);
        // Object-space ray with an unnormalised direction: t keeps its world meaning.
        const Ray local{transform_point(inst.to_object, ray.o),
                        transform_vector(inst.to_object, ray.d), limit};
        if (kAnyHit) {
            found = occluded_bvh(mesh.bvh, mesh.positions, mesh.indices, local);
            return found;
        }
        TriangleHit hit;
        if (!intersect_bvh(mesh.bvh, mesh.positions, mesh.indices, local, hit)) return false;
        limit = hit.t;
        found = true;
        const uint32_t* t = &mesh.indices[3 * hit.prim];
        const Vec3 p0 = transform_point(inst.to_world, mesh.positions[t[0]]);
        const Vec3 p1 = transform_point(inst.to_world, mesh.positions[t[1]]);
        const Vec3 p2 = transform_point(inst.to_world, mesh.positions[t[2]]);
        const float handed = glm::determinant(Mat3(inst.to_world)) < 0.0f ? -1.0f : 1.0f;
        *out = RayQueryHit{inst.id, hit.prim, hit.t,
                           (1.0f - hit.u - hit.v) * p0 + hit.u * p1 + hit.v * p2,
                           glm::normalize(glm::cross(p1 - p0, p2 - p0) * handed)};
        return false;
    });
    return found;
}

}  // namespace

std::optional<RayQueryHit> closest_hit(const AccelSnapshot& accel, const Ray& ray) {
    RayQueryHit hit;
    if (!trace<false>(accel, ray, &hit)) return std::nullopt;
    return hit;
}

bool any_hit(const AccelSnapshot& accel, const Ray& ray) {
    return trace<true>(accel, ray, nullptr);
}

void RayQueryService::publish(std::shared_ptr<const AccelSnapshot> snapshot) {
    std::lock_guard lock(mutex_);
    snapshot_ = std::move(snapshot);
}

std::shared_ptr<const AccelSnapshot> RayQueryService::snapshot() const {
    std::lock_guard lock(mutex_);
    return snapshot_;
}

std::optional<RayQueryHit> RayQueryService::closest_hit(const Ray& ray) const {
    const auto s = snapshot();
    return s ? coord::closest_hit(*s, ray) : std::nullopt;
}

bool RayQueryService::line_of_sight(const Vec3& from, const Vec3& to) const {
    const auto s = snapshot();
    const float dist = glm::distance(from, to);
    if (!s || !(dist > 0.0f)) return true;
    return !any_hit(*s, Ray{from, (to - from) / dist, dist * (1.0f - 1e-5f)});
}

uint64_t RayQueryService::frame() const {
    const auto s = snapshot();
    return s ? s->frame : 0;
}

}  // namespace pathfarm::coord
