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

Mat4 look_at_camera(const Vec3& eye, const Vec3& target, const Vec3& up) {
    // glm::lookAt builds world-to-camera for a camera looking down -Z; invert it.
    return glm::inverse(glm::lookAt(eye, target, up));
}

}  // namespace pathfarm
