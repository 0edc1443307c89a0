// Construction of node and camera transforms.
#include "common/math/transform.h"

#include <glm/gtc/matrix_transform.hpp>

namespace pathfarm {

Mat4 compose_trs(const Vec3& translation, const glm::quat& rotation, const Vec3& scale) {
    const Mat4 t = glm::translate(Mat4(1.0f), translation);
    const Mat4 r = glm::mat4_cast(rotation);
    const Mat4 s = glm::scale(Mat4(1.0f), scale);
    return t * r * s;
}

bool orients_view(const Vec3& forward, const Vec3& up) {
    const float f = glm::length(forward), u = glm::length(up);
    return f > 0.0f && u > 0.0f && glm::length(glm::cross(forward, up)) > 1e-3f * f * u;
}

Mat4 look_at_camera(const Vec3& eye, const Vec3& target, const Vec3& up) {
    const Vec3 forward = target - eye;
    Vec3 u = up;
    if (!orients_view(forward, up)) {
        const Vec3 a = glm::abs(forward);
        u = a.x <= a.y && a.x <= a.z ? Vec3(1, 0, 0) : a.y <= a.z ? Vec3(0, 1, 0) : Vec3(0, 0, 1);
    }
    // glm::lookAt builds world-to-camera for a camera looking down -Z; invert it.
    return glm::inverse(glm::lookAt(eye, target, u));
}

}  // namespace pathfarm
