// Light sampling only, BSDF sampling only and MIS are three estimators of the same integral:
// their images must agree within statistical error. Variance comes from batch means over
// independent seeds (samples within one render are correlated by the Sobol sequence); the
// per-pixel Welch tests are Šidák-corrected, and one more test compares image means.
#include <tuple>

#include <gtest/gtest.h>

#include "common/scene/load/builtin_scenes.h"
#include "tests/support/render_helpers.h"

namespace pathfarm::estimator_agreement_test {
namespace {

constexpr double kAlpha = 0.01;
constexpr int kBatches = 24;

std::vector<FloatImage> batches(const SceneModel& scene, LightStrategy strategy, int spp,
                                int size = 24, int light_candidates = 1) {
    std::vector<FloatImage> out;
    for (int b = 0; b < kBatches; ++b) {
        test::RenderRequest r;
        r.width = r.height = size;
        r.spp = spp;
        r.seed = 1000 + uint32_t(b) +
                 (strategy == LightStrategy::mis          ? 0
                  : strategy == LightStrategy::light_only ? 100
                                                          : 200);
        r.integrator.strategy = strategy;
        r.integrator.max_depth = 5;
        r.integrator.light_candidates = light_candidates;
        r.seed += 1000 * uint32_t(light_candidates - 1);
        out.push_back(test::render(scene, r));
    }
    return out;
}

TEST(EstimatorAgreement, CornellBoxMisLightAndBsdfAgree) {
    const SceneModel scene = make_cornell_box();
    const auto mis = batches(scene, LightStrategy::mis, 16);
    const auto light = batches(scene, LightStrategy::light_only, 16);
    const auto bsdf = batches(scene, LightStrategy::bsdf_only, 32);
    for (const auto& [name, other, block, sparse] :
         {std::tuple{"light", &light, 1, false}, std::tuple{"bsdf", &bsdf, 4, true}}) {
        const auto r = test::compare_batches(mis, *other, kAlpha, block, sparse);
        EXPECT_TRUE(r.agree(kAlpha))
            << "mis vs " << name << ": min pixel p " << r.min_pixel_p << " (threshold "
            << r.pixel_threshold << "), mean p " << r.mean_p << "; worst value " << r.worst_value
            << " (pixel " << r.worst_value / 3 % 24 << "," << r.worst_value / 72
            << "): " << r.worst_a << " vs " << r.worst_b;
    }
}

TEST(EstimatorAgreement, DefaultSceneMisAndLightAgree) {
    // Glossy, metal, glass, textures, sun and sky, several lights.
    const SceneModel scene = make_default_scene();
    const auto r = test::compare_batches(batches(scene, LightStrategy::mis, 8, 20),
                                         batches(scene, LightStrategy::light_only, 8, 20), kAlpha);
    EXPECT_TRUE(r.agree(kAlpha)) << "min pixel p " << r.min_pixel_p << " mean p " << r.mean_p;
}

// Resampled light selection among many emitters of several orientations (many-lights: 2 048
// emissive triangles; the default scene: lamps, a switched light, the sun and sky): light
// sampling alone with 4 candidates per sample agrees with MIS without resampling.
TEST(EstimatorAgreement, ResampledLightSelectionAgreesAmongManyLights) {
    for (const char* name : {"many-lights", "default"}) {
        const SceneModel scene = make_builtin_scene(name).value();
        const auto r =
            test::compare_batches(batches(scene, LightStrategy::mis, 4, 20),
                                  batches(scene, LightStrategy::light_only, 4, 20, 4), kAlpha);
        EXPECT_TRUE(r.agree(kAlpha))
            << name << ": min pixel p " << r.min_pixel_p << " mean p " << r.mean_p
            << "; worst value " << r.worst_value << ": " << r.worst_a << " vs " << r.worst_b;
    }
}

TEST(EstimatorAgreement, DetectsASmallBias) {
    // The same comparison must reject an estimator biased by 3%.
    const SceneModel scene = make_cornell_box();
    const auto a = batches(scene, LightStrategy::mis, 16);
    auto b = batches(scene, LightStrategy::light_only, 16);
    for (FloatImage& img : b)
        for (float& v : img.rgb)
            v *= 1.03f;
    EXPECT_FALSE(test::compare_batches(a, b, kAlpha).agree(kAlpha));
}

}  // namespace
}  // namespace pathfarm::estimator_agreement_test
