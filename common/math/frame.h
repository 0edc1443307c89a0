// Orthonormal frames around a normal (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited"): branch-free and continuous except at n.z = -1's sign flip.
#pragma once

#include "common/math/types.h"

namespace pathfarm {

struct Frame {
    Vec3 t, b, n;

    static Frame from_normal(const Vec3& n) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sign + n.z);
        const float c = n.x * n.y * a;
        return Frame{Vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x),
                     Vec3(c, sign + n.y * n.y * a, -n.y), n};
    }

    // A frame whose tangent follows t (projected to be orthogonal to n).
    static Frame from_normal_tangent(const Vec3& n, const Vec3& t_hint) {
        Vec3 t = t_hint - n * glm::dot(n, t_hint);
        const float len2 = glm::dot(t, t);
        if (!(len2 > 1e-12f)) return from_normal(n);
        t *= 1.0f / std::sqrt(len2);
        return Frame{t, glm::cross(n, t), n};
    }

    Vec3 to_local(const Vec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
    Vec3 to_world(const Vec3& v) const { return t * v.x + b * v.y + n * v.z; }
};

}  // namespace pathfarm
