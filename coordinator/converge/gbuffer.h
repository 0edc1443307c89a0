// The primary-hit G-buffer the coordinator traces for reprojection (one ray through each
// pixel centre against its own BVH of the frame). Tracers return radiance only; the
// coordinator computes this while they render, so the wire format does not grow.
#pragma once

#include <cstdint>
#include <vector>

#include "common/scene/camera.h"
#include "coordinator/accel/accel_updater.h"

namespace pathfarm::coord {

struct GBuffer {
    int width = 0, height = 0;
    std::vector<float> distance;     // along the unit primary ray; +inf where the ray escapes
    std::vector<uint32_t> instance;  // instance id; kNoInstance where the ray escapes
    std::vector<Vec3> position;      // world-space hit point (undefined where it escapes)

    static constexpr uint32_t kNoInstance = 0;  // instance ids start at 1
    bool hit(std::size_t i) const { return instance[i] != kNoInstance; }
};

GBuffer trace_gbuffer(const AccelSnapshot& accel, const Camera& camera, int width, int height);

// The G-buffer of `accel` for the camera `previous` was traced with, re-tracing only the
// screen rectangles that instances which changed since `previous_accel` (moved, deformed,
// added or removed) covered before or cover now. Falls back to a full trace where a changed
// box reaches behind the camera. Equal to a full trace: every other pixel's ray meets the
// same geometry as before.
GBuffer update_gbuffer(const GBuffer& previous, const AccelSnapshot& previous_accel,
                       const AccelSnapshot& accel, const Camera& camera,
                       std::size_t* traced_pixels = nullptr);

// Maps world points and directions to continuous pixel coordinates (pixel centres at +0.5):
// the inverse of generate_camera_ray. False when behind the camera.
class CameraProjector {
public:
    CameraProjector(const Camera& camera, int width, int height);
    bool point(const Vec3& p, float& px, float& py) const;
    bool direction(const Vec3& d, float& px, float& py) const;  // a point at infinity: the sky
    Vec3 eye() const { return eye_; }

private:
    bool camera_space(const Vec3& q, float& px, float& py) const;

    Mat4 world_to_camera_;
    Vec3 eye_;
    float scale_x_, scale_y_;
    int width_, height_;
};

}  // namespace pathfarm::coord
