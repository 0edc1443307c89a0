// Lights that cannot contribute are not sampled: an emitter switched off by the application
// (emission 0) leaves the light list, zero-power triangles are never chosen.
#include <gtest/gtest.h>

#include "common/render/light_sampler.h"
#include "common/render/shading_scene.h"
#include "common/scene/load/builtin_scenes.h"

namespace pathfarm {
namespace {

std::size_t emissive_triangles(const SceneModel& scene) {
    const ShadingScene shading(scene);
    return LightSampler(shading).triangle_count();
}

class LightSamplerSelection : public ::testing::TestWithParam<LightSelection> {};

TEST_P(LightSamplerSelection, SwitchedOffLightsAreNotSampled) {
    SceneModel scene = make_many_lights_scene();
    const std::size_t all = emissive_triangles(scene);
    EXPECT_EQ(all, 2048u) << "1024 panels of two triangles";
    for (Material& m : scene.materials)
        if (m.name == "panel-0") m.emissive_factor = Rgb(0.0f);  // the application switches it off
    const std::size_t left = emissive_triangles(scene);
    EXPECT_LT(left, all);
    EXPECT_GT(left, 0u);
    // Every remaining light can be chosen and none of the switched-off ones is.
    const ShadingScene shading(scene);
    const LightSampler lights(shading, {}, GetParam());
    for (int i = 0; i < 2000; ++i) {
        const auto s = lights.sample(Vec3(0.0f, 1.0f, 0.0f), Vec3(0.0f, 1.0f, 0.0f),
                                     (float(i) + 0.5f) / 2000.0f, Vec2(0.3f, 0.6f));
        ASSERT_TRUE(s.has_value());
        EXPECT_GT(max_component(s->radiance), 0.0f);
    }
}

INSTANTIATE_TEST_SUITE_P(Selections, LightSamplerSelection,
                         ::testing::Values(LightSelection::power, LightSelection::tree),
                         [](const auto& param) {
                             return param.param == LightSelection::tree ? "tree" : "power";
                         });

}  // namespace
}  // namespace pathfarm
