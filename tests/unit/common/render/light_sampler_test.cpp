// Lights that cannot contribute are not sampled: an emitter switched off by the application
// (emission 0) leaves the light list, zero-power triangles are never chosen.
#include <cstdio>
#include <memory>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

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

namespace pathfarm {
namespace {

// builtin:light-field with its ring turned by `angle` (what the animation does each frame).
SceneModel light_field_turned(float angle) {
    SceneModel scene = make_light_field_scene();
    for (Instance& inst : scene.instances)
        if (scene.nodes[std::size_t(inst.node)].name == "ring")
            inst.transform = glm::rotate(Mat4(1.0f), angle, Vec3(0, 1, 0)) * inst.transform;
    return scene;
}

double pmf_sum(const LightSampler& lights, const Vec3& p, const Vec3& n) {
    double sum = 0.0;
    for (uint32_t k = 0; k < lights.triangle_count(); ++k)
        sum += lights.tree().pmf(p, n, k);
    return sum;
}

// A moving emitter refits the last frame's tree: the same emitters, every one inside its
// ancestors (light_tree_test.cpp checks the bounds), probabilities still summing to one; a
// light switched off changes the emitter list and builds anew.
TEST(LightSamplerTree, MovedEmittersRefitTheLastTreeAndSwitchedOnesRebuildIt) {
    const SceneModel first = light_field_turned(0.0f);
    const ShadingScene shading0(first);
    LightSampler previous(shading0, {}, LightSelection::tree);
    EXPECT_EQ(previous.triangle_count(), 9892u);
    EXPECT_FALSE(previous.tree_refitted());
    const SceneModel moved = light_field_turned(0.05f);
    const ShadingScene shading1(moved);
    LightSampler refitted(shading1, {}, LightSelection::tree, &previous);
    EXPECT_TRUE(refitted.tree_refitted());
    for (const Vec3& p : {Vec3(0.0f, 1.0f, 0.0f), Vec3(1.5f, 0.2f, -1.0f), Vec3(0.8f, 2.3f, 0.0f)})
        EXPECT_NEAR(pmf_sum(refitted, p, Vec3(0.0f, 1.0f, 0.0f)), 1.0, 1e-4);
    // A whole turn of the ring, frame by frame: mostly refitted; rebuilt when the ring's
    // emitters have drifted from the fireflies they shared nodes with.
    std::vector<std::unique_ptr<SceneModel>> models;
    std::vector<std::unique_ptr<ShadingScene>> shadings;
    std::unique_ptr<LightSampler> last;
    double worst = 1.0;
    int rebuilds = 0;
    for (int step = 0; step <= 126; ++step) {
        models.push_back(std::make_unique<SceneModel>(light_field_turned(0.05f * float(step))));
        shadings.push_back(std::make_unique<ShadingScene>(*models.back()));
        last = std::make_unique<LightSampler>(*shadings.back(), std::vector<bool>{},
                                              LightSelection::tree, last.get());
        rebuilds += step > 0 && !last->tree_refitted();
        worst = std::max(worst, last->tree_cost_ratio());
    }
    EXPECT_LE(worst, LightSampler::kRefitCostLimit);
    EXPECT_LE(rebuilds, 12) << "a turn of 126 frames";
    std::printf("a turn of the ring (126 frames): %d rebuilds, cost at most %.3fx the built\n",
                rebuilds, worst);
    // Emitters trading places (each moved onto another's spot): the refitted tree's nodes
    // span the room, its cost grows past the limit and it is built anew.
    SceneModel shuffled = first;
    std::vector<std::size_t> ring;
    for (std::size_t i = 0; i < shuffled.instances.size(); ++i)
        if (shuffled.nodes[std::size_t(shuffled.instances[i].node)].name == "ring")
            ring.push_back(i);
    ASSERT_GE(ring.size(), 2u);
    for (std::size_t k = 0; k < ring.size(); ++k)  // each colour's ring mesh moved across
        shuffled.instances[ring[k]].transform =
            glm::translate(Mat4(1.0f), Vec3(k % 2 ? 1.2f : -1.2f, -1.5f, 0.0f)) *
            shuffled.instances[ring[k]].transform;
    const ShadingScene shading_shuffled(shuffled);
    LightSampler fresh(shading0, {}, LightSelection::tree);
    const LightSampler rebuilt_after_shuffle(shading_shuffled, {}, LightSelection::tree, &fresh);
    EXPECT_FALSE(rebuilt_after_shuffle.tree_refitted());
    SceneModel dark = moved;
    for (Material& m : dark.materials)
        if (m.name == "led-3") m.emissive_factor = Rgb(0.0f);
    const ShadingScene shading2(dark);
    LightSampler again(shading1, {}, LightSelection::tree);
    const LightSampler rebuilt(shading2, {}, LightSelection::tree, &again);
    EXPECT_FALSE(rebuilt.tree_refitted());
    EXPECT_LT(rebuilt.triangle_count(), refitted.triangle_count());
}

}  // namespace
}  // namespace pathfarm
