// G-buffer tracing (TBB over rows) and the inverse of generate_camera_ray.
#include "coordinator/converge/gbuffer.h"

#include <tbb/parallel_for.h>

#include "common/math/transform.h"
#include "coordinator/query/ray_query.h"

namespace pathfarm::coord {

GBuffer trace_gbuffer(const AccelSnapshot& accel, const Camera& camera, int width, int height) {
    GBuffer g;
    g.width = width;
    g.height = height;
    const std::size_t n = std::size_t(width) * height;
    g.distance.assign(n, kInfinity);
    g.instance.assign(n, GBuffer::kNoInstance);
    g.position.assign(n, Vec3(0.0f));
    tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            const Ray ray = generate_camera_ray(camera, width, height, x + 0.5f, y + 0.5f);
            const auto hit = closest_hit(accel, ray);
            if (!hit) continue;
            const std::size_t i = std::size_t(y) * width + x;
            g.distance[i] = hit->distance;
            g.instance[i] = hit->instance;
            g.position[i] = hit->point;
        }
    });
    return g;
}

CameraProjector::CameraProjector(const Camera& camera, int width, int height)
    : world_to_camera_(glm::inverse(camera.camera_to_world)),
      eye_(transform_point(camera.camera_to_world, Vec3(0.0f))),
      scale_y_(std::tan(0.5f * camera.yfov_radians)),
      width_(width),
      height_(height) {
    scale_x_ = scale_y_ * float(width) / float(height);
}

bool CameraProjector::camera_space(const Vec3& q, float& px, float& py) const {
    if (!(q.z < 0.0f)) return false;  // the camera looks down -Z
    px = (q.x / -q.z / scale_x_ + 1.0f) * 0.5f * float(width_);
    py = (1.0f - q.y / -q.z / scale_y_) * 0.5f * float(height_);
    return std::isfinite(px) && std::isfinite(py);
}

bool CameraProjector::point(const Vec3& p, float& px, float& py) const {
    return camera_space(transform_point(world_to_camera_, p), px, py);
}

bool CameraProjector::direction(const Vec3& d, float& px, float& py) const {
    return camera_space(transform_vector(world_to_camera_, d), px, py);
}

}  // namespace pathfarm::coord
