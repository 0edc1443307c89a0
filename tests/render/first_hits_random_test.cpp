// First hits through mirrors and glass in random scenes (a test that searches): a floor and a
// back wall, and spheres and tilted quads of random size, place and material (mirror, clear
// glass, rough glass, glossy and rough plastic, emitter), seen from random cameras. On every
// backend each pixel's first hit is finite, unit-normalled and facing the camera; a replaced
// one lies beyond the surface the centre ray meets first and is what a brute-force chain in
// double precision finds; the OpenCL backend's flags are Embree's.
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/render/path_tracer.h"
#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_builder.h"
#include "tests/support/first_hit_reference.h"
#include "tests/support/render_helpers.h"

namespace pathfarm::first_hits_random_test {
namespace {

using tracer::BackendKind;

constexpr int kW = 48, kH = 32;

float uniform(std::mt19937& rng, float lo, float hi) {
    return lo + (hi - lo) * float(rng() >> 8) * (1.0f / 16777216.0f);
}

Material material_kind(int kind) {
    Material m;
    m.name = "kind" + std::to_string(kind);
    m.base_color_factor = Vec4(0.8f, 0.7f, 0.6f, 1.0f);
    switch (kind) {
        case 0:
            m.metallic_factor = 1.0f, m.roughness_factor = 0.0f;
            break;  // mirror
        case 1:
            m.transmission_factor = 1.0f, m.roughness_factor = 0.0f;
            break;  // clear glass
        case 2:
            m.transmission_factor = 1.0f, m.roughness_factor = 0.5f;
            break;  // rough glass
        case 3:
            m.roughness_factor = 0.25f;
            break;  // glossy
        case 4:
            m.roughness_factor = 0.8f;
            break;  // rough
        default:
            m.emissive_factor = Rgb(2.0f);
            break;  // emitter
    }
    return m;
}

// Scene `index`: a floor, a back wall and six objects of random kinds.
SceneModel random_scene(uint32_t index) {
    std::mt19937 rng(1000 + index);
    SceneBuilder b("first-hits-random-" + std::to_string(index));
    std::vector<int> kinds;
    for (int k = 0; k < 6; ++k)
        kinds.push_back(b.add_material(material_kind(k)));
    const int plain = kinds[4];
    b.add_instance(b.add_mesh(make_quad({0, 0, 0}, {6, 0, 0}, {0, 0, -6}, plain)), Mat4(1.0f));
    b.add_instance(b.add_mesh(make_quad({0, 2, -3}, {6, 0, 0}, {0, 4, 0}, plain)), Mat4(1.0f));
    for (int o = 0; o < 6; ++o) {
        const int material = kinds[rng() % kinds.size()];
        const Vec3 at(uniform(rng, -2.0f, 2.0f), uniform(rng, 0.3f, 2.0f),
                      uniform(rng, -2.5f, 0.5f));
        const float size = uniform(rng, 0.3f, 1.2f);
        Mat4 place = glm::translate(Mat4(1.0f), at);
        place = glm::rotate(
            place, uniform(rng, 0.0f, 6.28f),
            glm::normalize(Vec3(uniform(rng, -1.0f, 1.0f), 1.0f, uniform(rng, -1.0f, 1.0f))));
        const Mesh mesh = rng() % 2 ? make_sphere(0.5f * size, 12, 24, material)
                                    : make_quad({0, 0, 0}, {size, 0, 0}, {0, size, 0}, material);
        b.add_instance(b.add_mesh(mesh), place);
    }
    Camera camera;
    const Vec3 eye(uniform(rng, -1.5f, 1.5f), uniform(rng, 1.0f, 2.5f), uniform(rng, 2.0f, 3.5f));
    camera.camera_to_world = glm::inverse(
        glm::lookAt(eye, Vec3(uniform(rng, -0.5f, 0.5f), 1.0f, -1.0f), Vec3(0.0f, 1.0f, 0.0f)));
    camera.yfov_radians = glm::radians(55.0f);
    b.add_camera(camera);
    return b.finish();
}

std::vector<FirstHit> first_hits(const SceneModel& scene, BackendKind kind) {
    auto backend = tracer::create_backend(kind, tracer::BackendOptions{2, 0, 0});
    EXPECT_TRUE(backend.ok() && (*backend)->set_scene(scene).ok());
    std::vector<float> rgb(std::size_t(kW) * kH * 3);
    std::vector<FirstHit> hits(std::size_t(kW) * kH);
    const tracer::RenderJob job{FrameSpec{kW, kH, 0, 1, 1, 0, scene.cameras.at(0)},
                                IntegratorSettings{},
                                0,
                                kH,
                                {},
                                hits.data()};
    EXPECT_TRUE((*backend)->render_rows(job, rgb.data()).ok());
    return hits;
}

class FirstHitsRandom : public ::testing::TestWithParam<BackendKind> {};

TEST_P(FirstHitsRandom, ThroughMirrorsAndGlassAreWhatABruteForceChainFinds) {
    int replaced = 0, right = 0;
    for (uint32_t index = 0; index < 12; ++index) {
        const SceneModel scene = random_scene(index);
        const std::vector<FirstHit> hits = first_hits(scene, GetParam());
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const std::string where = "scene " + std::to_string(index) + " pixel " +
                                          std::to_string(x) + "," + std::to_string(y);
                const Ray ray =
                    generate_camera_ray(scene.cameras.at(0), kW, kH, x + 0.5f, y + 0.5f);
                const FirstHit& got = hits[std::size_t(y) * kW + x];
                if (!got.hit()) continue;
                ASSERT_TRUE(std::isfinite(got.distance) && got.distance > 0.0f) << where;
                ASSERT_NEAR(glm::length(got.normal), 1.0f, 1e-3f) << where;
                ASSERT_LE(glm::dot(got.normal, ray.d), 1e-6f) << where;
                ASSERT_TRUE(glm::all(glm::greaterThanEqual(got.albedo, Rgb(0.0f))) &&
                            glm::all(glm::lessThanEqual(got.albedo, Rgb(1.0f))))
                    << where;
                if (!got.replaced()) continue;
                ++replaced;
                ASSERT_FALSE(got.sharp()) << where;
                ASSERT_EQ(got.primitive, FirstHit::kNone) << where;
                const test::ReferenceHit first = test::brute_force(scene, ray);
                ASSERT_NE(first.instance, FirstHit::kNone) << where;
                EXPECT_GT(got.distance, float(first.t)) << where << ": beyond the first hit";
                const test::Beyond want = test::follow_through(scene, ray, first);
                right += want.replaced && want.instance == got.instance &&
                         std::abs(got.distance - want.travelled) < 1e-3 * want.travelled &&
                         glm::dot(glm::dvec3(got.normal), want.normal) > 0.999;
            }
    }
    EXPECT_GT(replaced, 200) << "the random scenes show mirrors and glass";
    // Chains through spheres amplify float rounding; a few end on another surface.
    EXPECT_GE(right, replaced * 9 / 10) << right << " of " << replaced;
}

INSTANTIATE_TEST_SUITE_P(Backends, FirstHitsRandom, ::testing::ValuesIn(test::built_backends()),
                         test::BackendTestName{});

#ifdef PATHFARM_HAS_OPENCL
TEST(FirstHitsRandomAcrossBackends, OpenClFlagsAreEmbrees) {
    int same = 0, total = 0;
    for (uint32_t index = 0; index < 12; ++index) {
        const SceneModel scene = random_scene(index);
        const std::vector<FirstHit> e = first_hits(scene, BackendKind::embree);
        const std::vector<FirstHit> c = first_hits(scene, BackendKind::opencl);
        for (std::size_t i = 0; i < e.size(); ++i) {
            if (!e[i].hit()) continue;
            ++total;
            same += e[i].flags == c[i].flags && e[i].instance == c[i].instance;
        }
    }
    EXPECT_GE(same, total * 98 / 100) << same << " of " << total;
}
#endif

}  // namespace
}  // namespace pathfarm::first_hits_random_test
