// Random geometry for tests that search configurations: directions uniform on the sphere.
#pragma once

#include <random>

#include "common/math/types.h"

namespace pathfarm::test {

// A direction uniform on the unit sphere (a normalised Gaussian vector).
inline Vec3 random_direction(std::mt19937& rng) {
    std::normal_distribution<float> g;
    for (;;) {
        const Vec3 v(g(rng), g(rng), g(rng));
        if (glm::length(v) > 1e-3f) return glm::normalize(v);
    }
}

}  // namespace pathfarm::test
