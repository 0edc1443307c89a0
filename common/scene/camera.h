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
    Ray operator()(float px, float py) const;

private:
    Mat4 camera_to_world_;
    Vec3 eye_;
    float tan_half_, aspect_, width_, height_;
};

// The default framing for scenes without a camera: looking down -Z at the bounding box, yfov
// 45 degrees, far enough back that the whole box fits the view for the given aspect.
Camera frame_bounds(const Bounds3f& bounds, float aspect);

}  // namespace pathfarm
