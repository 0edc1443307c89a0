// Renders with known answers (pbrt's integrators_test): the furnace (every surface emits E and
// reflects albedo a, so every pixel is E / (1 - a): tests Russian roulette, MIS weights and the
// area-light pdfs together), and a Lambert sphere in an emitting enclosure (rho * E).
#include <gtest/gtest.h>

#include "common/scene/load/builtin_scenes.h"
#include "tests/support/render_helpers.h"

namespace pathfarm {
namespace {

struct Stats {
    double mean = 0.0, max_dev = 0.0;
};

Stats stats(const FloatImage& img, double expected) {
    Stats s;
    for (float v : img.rgb) {
        s.mean += v;
        s.max_dev = std::max(s.max_dev, std::abs(v - expected));
    }
    s.mean /= double(img.rgb.size());
    return s;
}

class Furnace : public ::testing::TestWithParam<LightStrategy> {};

TEST_P(Furnace, EveryPixelIsEmissionOverOneMinusAlbedo) {
    const SceneModel scene = test::make_furnace(0.5f, 0.5f);
    test::RenderRequest r;
    r.spp = 64;
    r.integrator.max_depth = 100;
    r.integrator.strategy = GetParam();
    const FloatImage img = test::render(scene, r);
    const Stats s = stats(img, 1.0);
    EXPECT_NEAR(s.mean, 1.0, 0.01);
    EXPECT_LT(s.max_dev, 0.2);
    EXPECT_EQ(count_nonfinite(img), 0u);
}

TEST_P(Furnace, LambertSphereReflectsRhoTimesEmission) {
    const SceneModel scene = test::make_lit_sphere(2.0f, 0.6f);
    test::RenderRequest r;
    r.spp = 256;  // light sampling alone is the noisiest of the three here
    r.integrator.strategy = GetParam();
    const FloatImage img = test::render(scene, r);
    // The centre pixels see the sphere, the corners the enclosure.
    double centre = 0.0;
    for (int y = 12; y < 20; ++y)
        for (int x = 12; x < 20; ++x)
            centre += luminance(img.pixel(x, y)) / 64.0;
    EXPECT_NEAR(centre, 1.2, 0.03);
    EXPECT_NEAR(luminance(img.pixel(0, 0)), 2.0, 1e-4);
}

INSTANTIATE_TEST_SUITE_P(AllStrategies, Furnace,
                         ::testing::Values(LightStrategy::mis, LightStrategy::light_only,
                                           LightStrategy::bsdf_only),
                         [](const auto& param_info) {
                             return std::string(param_info.param == LightStrategy::mis ? "mis"
                                                : param_info.param == LightStrategy::light_only
                                                    ? "light"
                                                    : "bsdf");
                         });

TEST(Furnace, TheBuiltinFurnaceIsOneEverywhereThroughTheLightTree) {
    // builtin:furnace: 5 000 emitting triangles around the ball, so next-event estimation and
    // the MIS weights of emitter hits go through a light tree of several levels.
    const Result<SceneModel> scene = make_builtin_scene("furnace");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    ASSERT_EQ(scene->meshes[scene->instances[0].mesh].triangle_count(), 5000u);
    test::RenderRequest r;
    r.spp = 32;
    r.integrator.max_depth = 100;
    r.integrator.light_selection = LightSelection::tree;
    const Stats s = stats(test::render(*scene, r), 1.0);
    EXPECT_NEAR(s.mean, 1.0, 0.01);
    EXPECT_LT(s.max_dev, 0.3);
}

TEST(Furnace, TruncatingPathsIsDetected) {
    // With 2 bounces the furnace cannot reach 1: proves the test above can fail.
    test::RenderRequest r;
    r.spp = 32;
    r.integrator.max_depth = 2;
    const Stats s = stats(test::render(test::make_furnace(0.5f, 0.5f), r), 1.0);
    EXPECT_NEAR(s.mean, 0.875, 0.01);  // 0.5 + 0.25 + 0.125
}

}  // namespace
}  // namespace pathfarm
