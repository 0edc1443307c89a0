// Lights that cannot contribute are not sampled: an emitter switched off by the application
// (emission 0) leaves the light list, zero-power triangles are never chosen.
#include <cstdio>
#include <cstring>
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

// Two trees chose alike for every receiver: the same nodes, trails and shares, bit for bit.
void expect_same_tree(const LightTree& a, const LightTree& b, const char* what) {
    ASSERT_EQ(a.wide_nodes().size(), b.wide_nodes().size()) << what;
    EXPECT_EQ(0, std::memcmp(a.wide_nodes().data(), b.wide_nodes().data(),
                             a.wide_nodes().size() * sizeof(LightTree::WideNode)))
        << what;
    EXPECT_EQ(a.trails(), b.trails()) << what;
    EXPECT_EQ(a.leaf_shares(), b.leaf_shares()) << what;
}

// The tree of a state is a function of that state alone (docs/determinism.md item 6): built
// with the per-mesh topologies a backend kept from earlier states, it equals the tree a fresh
// sampler builds, bit for bit, while the ring turns, when its meshes trade places across the
// room and when a light is switched off; and kept topologies are not built again.
TEST(LightSamplerTree, KeptTopologiesGiveTheFreshTreeAndAreNotRebuilt) {
    LightTopologyCache cache;
    std::size_t first_builds = 0;
    for (int step = 0; step <= 12; ++step) {
        const SceneModel scene = light_field_turned(0.05f * float(step));
        const ShadingScene shading(scene);
        const LightSampler kept(shading, {}, LightSelection::tree, &cache);
        if (step == 0) {
            EXPECT_EQ(kept.triangle_count(), 9892u);
            first_builds = cache.builds();
            for (const Vec3& p : {Vec3(0, 1, 0), Vec3(1.5f, 0.2f, -1.0f), Vec3(0.8f, 2.3f, 0)})
                EXPECT_NEAR(pmf_sum(kept, p, Vec3(0, 1, 0)), 1.0, 1e-4);
        }
        if (step % 6 == 0)
            expect_same_tree(kept.tree(), LightSampler(shading, {}, LightSelection::tree).tree(),
                             "a turned ring");
    }
    EXPECT_EQ(cache.builds(), first_builds) << "a turning ring keeps its meshes' topologies";
    SceneModel shuffled = light_field_turned(0.0f);
    for (std::size_t i = 0, k = 0; i < shuffled.instances.size(); ++i)
        if (shuffled.nodes[std::size_t(shuffled.instances[i].node)].name == "ring")
            shuffled.instances[i].transform =
                glm::translate(Mat4(1.0f), Vec3(k++ % 2 ? 1.2f : -1.2f, -1.5f, 0.0f)) *
                shuffled.instances[i].transform;
    SceneModel dark = shuffled;
    for (Material& m : dark.materials)
        if (m.name == "led-3") m.emissive_factor = Rgb(0.0f);
    for (const SceneModel* scene : {&shuffled, &dark}) {
        const ShadingScene shading(*scene);
        const LightSampler kept(shading, {}, LightSelection::tree, &cache);
        const LightSampler fresh(shading, {}, LightSelection::tree);
        expect_same_tree(kept.tree(), fresh.tree(), scene == &dark ? "dark" : "shuffled");
        if (scene == &dark) {
            EXPECT_LT(kept.triangle_count(), 9892u);
        }
    }
    EXPECT_EQ(cache.builds(), first_builds) << "moved or switched, the meshes are the same";
}

}  // namespace
}  // namespace pathfarm
