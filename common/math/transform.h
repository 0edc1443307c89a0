// Affine transforms of points, vectors and normals (column-major glm matrices).
#pragma once

#include <glm/gtc/quaternion.hpp>

#include "common/math/types.h"

namespace pathfarm {

inline Vec3 transform_point(const Mat4& m, const Vec3& p) { return Vec3(m * Vec4(p, 1.0f)); }
inline Vec3 transform_vector(const Mat4& m, const Vec3& v) { return Vec3(m * Vec4(v, 0.0f)); }

// The matrix that maps object-space normals to world space: inverse transpose of the upper 3x3.
inline Mat3 normal_matrix(const Mat4& m) { return glm::transpose(glm::inverse(Mat3(m))); }

// Translation * rotation * scale, the glTF node convention.
Mat4 compose_trs(const Vec3& translation, const glm::quat& rotation, const Vec3& scale);

// Whether `up` can orient a camera looking along `forward`: not zero and not within about a
// twentieth of a degree of parallel to it (glm::lookAt's basis is NaN there).
bool orients_view(const Vec3& forward, const Vec3& up);

// A camera-to-world matrix looking from eye towards target (another point) with the given up
// vector; the camera looks down its local -Z axis with +Y up (glTF convention). Where `up`
// does not orient the view (orients_view: a camera looking straight down with +Y up) the world
// axis least aligned with the view takes its place: the roll is arbitrary but the matrix is
// never NaN (a NaN camera renders a black frame, silently). Command lines reject such an up
// instead.
Mat4 look_at_camera(const Vec3& eye, const Vec3& target, const Vec3& up);

}  // namespace pathfarm
