// Camera ray generation and default framing.
#include "common/scene/camera.h"

#include "common/math/transform.h"

namespace pathfarm {

Ray generate_camera_ray(const Camera& camera, int width, int height, float px, float py) {
    return CameraRays(camera, width, height)(px, py);
}

CameraRays::CameraRays(const Camera& camera, int width, int height)
    : camera_to_world_(camera.camera_to_world),
      eye_(transform_point(camera.camera_to_world, Vec3(0.0f))),
      tan_half_(std::tan(0.5f * camera.yfov_radians)),
      aspect_(float(width) / float(height)),
      width_(float(width)),
      height_(float(height)) {}

Camera frame_bounds(const Bounds3f& bounds, float aspect) {
    Camera camera;
    camera.name = "default-framing";
    if (bounds.empty()) return camera;
    const Vec3 center = bounds.center();
    const Vec3 half = 0.5f * bounds.extent();
    const float tan_half_y = std::tan(0.5f * camera.yfov_radians);
    const float tan_half_x = tan_half_y * aspect;
    // Distance from the box's front face (z = upper.z) so both half-extents fit, with 5% margin.
    const float dist = 1.05f * std::max(half.y / tan_half_y, half.x / tan_half_x);
    const Vec3 eye(center.x, center.y, bounds.upper.z + dist);
    camera.camera_to_world = look_at_camera(eye, center, Vec3(0.0f, 1.0f, 0.0f));
    return camera;
}

}  // namespace pathfarm
