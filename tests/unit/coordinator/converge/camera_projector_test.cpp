// CameraProjector::points (a row of points projected at once, in a loop that vectorises) gives
// what point() and glm::length(p - eye()) give one at a time, bit for bit: the temporal
// accumulator takes either path and its history must not depend on which.
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "coordinator/converge/gbuffer.h"

namespace pathfarm::coord {
namespace {

uint32_t bits(float f) { return std::bit_cast<uint32_t>(f); }

// Random cameras (position, orientation, field of view, image size) and points around them:
// in front, behind, in the eye's plane, far away, at the eye itself.
TEST(CameraProjector, PointsAtOnceAreEachPointAlone) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), angle(0.0f, 6.2831853f);
    std::uniform_real_distribution<float> fov(0.2f, 2.5f);
    std::uniform_int_distribution<int> size(8, 700);
    int compared = 0, on_screen = 0;
    for (int c = 0; c < 30; ++c) {
        Camera camera;
        camera.yfov_radians = fov(rng);
        const Vec3 eye(50.0f * u(rng), 50.0f * u(rng), 50.0f * u(rng));
        camera.camera_to_world =
            glm::translate(Mat4(1.0f), eye) *
            glm::rotate(Mat4(1.0f), angle(rng),
                        glm::normalize(Vec3(u(rng), u(rng), u(rng)) + Vec3(0.0f, 0.0f, 1e-3f)));
        const CameraProjector project(camera, size(rng), size(rng));
        const int n = 257;  // a vector's worth and a remainder
        std::vector<float> xs(n), ys(n), zs(n), px(n), py(n), distance(n);
        std::vector<int32_t> on(n);
        const Vec3 forward = transform_vector(camera.camera_to_world, Vec3(0.0f, 0.0f, -1.0f));
        const Vec3 right = transform_vector(camera.camera_to_world, Vec3(1.0f, 0.0f, 0.0f));
        for (int k = 0; k < n; ++k) {
            Vec3 p = project.eye() + Vec3(u(rng), u(rng), u(rng)) * std::pow(10.0f, 4.0f * u(rng));
            if (k % 17 == 0) p = project.eye();                   // the eye
            if (k % 19 == 0) p = project.eye() + right * u(rng);  // in the eye's plane
            if (k % 23 == 0) p = project.eye() + forward * (1e6f * std::abs(u(rng)));  // far
            xs[k] = p.x, ys[k] = p.y, zs[k] = p.z;
        }
        project.points(xs.data(), ys.data(), zs.data(), n, px.data(), py.data(), on.data(),
                       distance.data());
        for (int k = 0; k < n; ++k) {
            const Vec3 p(xs[k], ys[k], zs[k]);
            float ax = -7.0f, ay = -7.0f;
            const bool alone = project.point(p, ax, ay);
            ASSERT_EQ(on[k] != 0, alone) << "camera " << c << " point " << k;
            EXPECT_EQ(bits(distance[k]), bits(glm::length(p - project.eye())));
            if (alone) {
                EXPECT_EQ(bits(px[k]), bits(ax)) << "camera " << c << " point " << k;
                EXPECT_EQ(bits(py[k]), bits(ay)) << "camera " << c << " point " << k;
                ++on_screen;
            }
            ++compared;
        }
    }
    EXPECT_EQ(compared, 30 * 257);
    EXPECT_GT(on_screen, 1000);  // in front of the camera, or nothing was compared
    EXPECT_LT(on_screen, compared - 1000);
}

}  // namespace
}  // namespace pathfarm::coord
