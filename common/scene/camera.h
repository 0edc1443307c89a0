// Pinhole camera (glTF perspective): looks down its local -Z with +Y up. yfov is the full
// vertical field of view; the aspect ratio comes from the image (--width/--height).
#pragma once

#include <string>

#include "common/math/types.h"

namespace pathfarm {

struct Camera {
    std::string name;
    Mat4 camera_to_world{1.0f};
    float yfov_radians = glm::radians(45.0f);
};

// Primary ray through film position (px, py) in pixels: (0,0) is the top-left corner of the
// image, (width, height) the bottom-right.
Ray generate_camera_ray(const Camera& camera, int width, int height, float px, float py);

// generate_camera_ray for one camera and image size, with what every ray shares (the eye, the
// tangent of the half field of view) computed once: the same rays, bit for bit.
class CameraRays {
public:
    CameraRays(const Camera& camera, int width, int height);
    // Inline: the coordinator makes one per display pixel and frame (its G-buffer).
    Ray operator()(float px, float py) const {
        const float sx = (2.0f * px / width_ - 1.0f) * tan_half_ * aspect_;
        const float sy = (1.0f - 2.0f * py / height_) * tan_half_;
        Ray ray;
        ray.o = eye_;
        ray.d = glm::normalize(Vec3(camera_to_world_ * Vec4(sx, sy, -1.0f, 0.0f)));  // a vector
        return ray;
    }

private:
    Mat4 camera_to_world_;
    Vec3 eye_;
    float tan_half_, aspect_, width_, height_;
};

// The default framing for scenes without a camera: looking down -Z at the bounding box, yfov
// 45 degrees, far enough back that the whole box fits the view for the given aspect.
Camera frame_bounds(const Bounds3f& bounds, float aspect);

}  // namespace pathfarm
