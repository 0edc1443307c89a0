// Single-ray queries for game logic (Brigade §4.6): closest hit and line of sight against the
// acceleration structure of the last completed frame. Thread-safe: the game thread queries
// while the frame loop builds the next frame's structure and publishes it.
#pragma once

#include <memory>
#include <mutex>
#include <optional>

#include "coordinator/accel/accel_updater.h"

namespace pathfarm::coord {

struct RayQueryHit {
    uint32_t instance = 0;  // instance id in the SceneState
    uint32_t prim = 0;      // triangle of the instance's mesh
    float distance = 0.0f;  // along the (unit) query direction
    Vec3 point{0.0f};
    Vec3 normal{0.0f};  // unit geometric normal of the triangle's front face, world space
};

std::optional<RayQueryHit> closest_hit(const AccelSnapshot& accel, const Ray& ray);
bool any_hit(const AccelSnapshot& accel, const Ray& ray);  // something within ray.tmax

class RayQueryService {
public:
    void publish(std::shared_ptr<const AccelSnapshot> snapshot);
    std::optional<RayQueryHit> closest_hit(const Ray& ray) const;
    bool line_of_sight(const Vec3& from, const Vec3& to) const;
    uint64_t frame() const;  // frame of the structure queries see

private:
    std::shared_ptr<const AccelSnapshot> snapshot() const;

    mutable std::mutex mutex_;
    std::shared_ptr<const AccelSnapshot> snapshot_;
};

}  // namespace pathfarm::coord
