// Emitters in unreachable rooms are not sampled: SealedEmitters finds closed opaque surfaces
// and which side of them the emitters and the camera are on; the backends leave the separated
// emitters out of next-event estimation, which changes no expected value (tested bit for bit
// against the scene without those emitters, and statistically against not culling).
#include <cstring>

#include <gtest/gtest.h>

#include "common/math/transform.h"
#include "common/render/sealed_emitters.h"
#include "common/scene/load/builtin_scenes.h"
#include "tests/support/render_helpers.h"

namespace pathfarm {
namespace {

Vec3 eye(const SceneModel& scene) {
    return transform_point(scene.cameras.at(0).camera_to_world, Vec3(0.0f));
}

bool is_panel(const SceneModel& scene, std::size_t instance) {
    return scene.nodes[std::size_t(scene.instances[instance].node)].name == "panels";
}

bool is_emissive(const SceneModel& scene, std::size_t instance) {
    const Mesh& mesh = scene.meshes[std::size_t(scene.instances[instance].mesh)];
    return scene.materials[std::size_t(mesh.material)].is_emissive();
}

// The index of the k-th instance whose node is called `name` (k = 0: the camera's room).
std::size_t instance_named(const SceneModel& scene, const std::string& name, int k) {
    for (std::size_t i = 0; i < scene.instances.size(); ++i)
        if (scene.nodes[std::size_t(scene.instances[i].node)].name == name && k-- == 0) return i;
    ADD_FAILURE() << "no instance " << name;
    return 0;
}

TEST(SealedEmitters, PanelsInTheClosedRoomNextDoorAreCulled) {
    const SceneModel scene = make_sealed_lights_scene();
    const SealedEmitters sealed(scene);
    EXPECT_EQ(sealed.enclosure_count(), 2u);  // each room's six walls
    const std::vector<bool> culled = sealed.culled(eye(scene));
    std::size_t panels = 0;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        if (!is_emissive(scene, i)) {
            EXPECT_FALSE(culled[i]);
            continue;
        }
        EXPECT_EQ(culled[i], is_panel(scene, i)) << "instance " << i;
        panels += is_panel(scene, i);
    }
    EXPECT_EQ(panels, 8u);

    // From inside the other room it is the lamp that cannot be seen.
    const std::vector<bool> from_next_door = sealed.culled(Vec3(5.0f, 1.5f, 0.0f));
    for (std::size_t i = 0; i < scene.instances.size(); ++i)
        if (is_emissive(scene, i)) {
            EXPECT_EQ(from_next_door[i], !is_panel(scene, i));
        }
    // From between the rooms, both sides are cut off.
    const std::vector<bool> between = sealed.culled(Vec3(2.5f, 1.5f, 0.0f));
    for (std::size_t i = 0; i < scene.instances.size(); ++i)
        EXPECT_EQ(between[i], is_emissive(scene, i));
}

TEST(SealedEmitters, OpeningsGlassAndGapsKeepEveryEmitter) {
    const SceneModel sealed_scene = make_sealed_lights_scene();
    auto nothing_culled = [](const SceneModel& scene) {
        const std::vector<bool> culled = SealedEmitters(scene).culled(eye(scene));
        return std::none_of(culled.begin(), culled.end(), [](bool c) { return c; });
    };
    {  // the facing walls of both rooms removed: light flows through
        SceneModel open = sealed_scene;
        const std::size_t a = instance_named(open, "right", 0), b = instance_named(open, "left", 1);
        open.instances.erase(open.instances.begin() + std::ptrdiff_t(std::max(a, b)));
        open.instances.erase(open.instances.begin() + std::ptrdiff_t(std::min(a, b)));
        EXPECT_TRUE(nothing_culled(open));
    }
    {  // the same walls made of glass
        SceneModel glass = sealed_scene;
        Material m = glass.materials[0];
        m.transmission_factor = 1.0f;
        glass.materials.push_back(m);
        for (std::size_t i :
             {instance_named(glass, "right", 0), instance_named(glass, "left", 1)}) {
            glass.meshes.push_back(glass.meshes[std::size_t(glass.instances[i].mesh)]);
            glass.meshes.back().material = int(glass.materials.size()) - 1;
            glass.instances[i].mesh = int(glass.meshes.size()) - 1;
        }
        EXPECT_TRUE(nothing_culled(glass));
    }
    {  // a wall of each room moved by a millimetre: the rooms are no longer closed
        SceneModel gap = sealed_scene;
        for (std::size_t i : {instance_named(gap, "right", 0), instance_named(gap, "left", 1)})
            gap.instances[i].transform =
                glm::translate(Mat4(1.0f), Vec3(1e-3f, 0.0f, 0.0f)) * gap.instances[i].transform;
        EXPECT_TRUE(nothing_culled(gap));
    }
}

TEST(SealedEmitters, KeepsTheAnalysisWhenTheWholeSceneIsTranslated) {
    // What camera-relative rendering does when the camera moves: every instance shifts by the
    // same vector. The analysis is adopted, and viewers are taken in the new coordinates.
    const SceneModel scene = make_sealed_lights_scene();
    SealedEmitters sealed(scene);
    const Vec3 shift(-0.3f, -1.4f, -1.8f);
    SceneModel moved = scene;
    for (Instance& inst : moved.instances)
        inst.transform = glm::translate(Mat4(1.0f), shift) * inst.transform;
    ASSERT_TRUE(sealed.adopt_translated(moved));
    EXPECT_EQ(sealed.culled(eye(scene) + shift), SealedEmitters(scene).culled(eye(scene)));
    EXPECT_EQ(sealed.culled(Vec3(5.0f, 1.5f, 0.0f) + shift),
              SealedEmitters(scene).culled(Vec3(5.0f, 1.5f, 0.0f)));

    SceneModel one_moved = scene;
    one_moved.instances[0].transform =
        glm::translate(Mat4(1.0f), Vec3(0.5f, 0.0f, 0.0f)) * one_moved.instances[0].transform;
    EXPECT_FALSE(SealedEmitters(scene).adopt_translated(one_moved));
    SceneModel glass = scene;
    glass.materials[0].transmission_factor = 1.0f;
    EXPECT_FALSE(SealedEmitters(scene).adopt_translated(glass));
}

// What a turning ring of lights does each frame: only emitters move. The closed surfaces are
// kept and only the moved emitters' sides found again; the result equals a new analysis.
TEST(SealedEmitters, KeepsTheClosedSurfacesWhenOnlyEmittersMove) {
    const SceneModel scene = make_sealed_lights_scene();
    std::size_t panel = 0, lamp = 0, occluder = 0;
    for (std::size_t i = scene.instances.size(); i-- > 0;) {
        const Material& m = scene.materials[std::size_t(
            scene.meshes[std::size_t(scene.instances[i].mesh)].material)];
        if (is_panel(scene, i))
            panel = i;
        else if (is_emissive(scene, i))
            lamp = i;
        else if (!(m.transmission_factor > 0.0f) && !m.alpha_tested())
            occluder = i;
    }
    ASSERT_TRUE(is_panel(scene, panel) && is_emissive(scene, lamp) &&
                !is_emissive(scene, occluder));
    SceneModel moved = scene;  // a panel from next door into the camera's room, the lamp out
    moved.instances[panel].transform =
        glm::translate(Mat4(1.0f), Vec3(-5.0f, 0.0f, 0.0f)) * moved.instances[panel].transform;
    moved.instances[lamp].transform =
        glm::translate(Mat4(1.0f), Vec3(5.0f, 0.0f, 0.0f)) * moved.instances[lamp].transform;
    SealedEmitters sealed(scene);
    ASSERT_TRUE(sealed.adopt_moved_instances(moved));
    const SealedEmitters fresh(moved);
    for (const Vec3& viewer : {eye(scene), Vec3(5.0f, 1.5f, 0.0f), Vec3(2.5f, 1.5f, 0.0f)})
        EXPECT_EQ(sealed.culled(viewer), fresh.culled(viewer));
    EXPECT_FALSE(sealed.culled(eye(scene))[panel]) << "the panel is in the camera's room now";
    EXPECT_TRUE(sealed.culled(eye(scene))[lamp]) << "the lamp is next door now";

    SceneModel wall_moved = moved;
    wall_moved.instances[occluder].transform = glm::translate(Mat4(1.0f), Vec3(0.0f, 0.5f, 0.0f)) *
                                               wall_moved.instances[occluder].transform;
    EXPECT_FALSE(SealedEmitters(moved).adopt_moved_instances(wall_moved));
    SealedEmitters shifted(scene);
    SceneModel all_moved = scene;
    for (Instance& inst : all_moved.instances)
        inst.transform = glm::translate(Mat4(1.0f), Vec3(1.0f, 0.0f, 0.0f)) * inst.transform;
    ASSERT_TRUE(shifted.adopt_translated(all_moved));
    EXPECT_FALSE(shifted.adopt_moved_instances(all_moved)) << "not after a translation";
}

TEST(LightCulling, RecomputesOnlyWhenTheCameraOrTheSceneChanges) {
    const SceneModel scene = make_sealed_lights_scene();
    LightCulling culling;
    culling.set_scene(scene);
    EXPECT_TRUE(culling.update(eye(scene), true)) << "a new scene always asks for a rebuild";
    EXPECT_FALSE(culling.update(eye(scene), true)) << "same camera, every work unit: no work";
    const std::vector<bool> in_room = culling.excluded();
    EXPECT_FALSE(culling.update(eye(scene) + Vec3(0.1f, 0.0f, 0.0f), true))
        << "moved inside the same room: the same set";
    EXPECT_TRUE(culling.update(Vec3(5.0f, 1.5f, 0.0f), true)) << "into the other room";
    EXPECT_NE(culling.excluded(), in_room);
    EXPECT_TRUE(culling.update(Vec3(5.0f, 1.5f, 0.0f), false)) << "culling switched off";
    EXPECT_TRUE(culling.excluded().empty());
    culling.set_scene(scene);
    EXPECT_TRUE(culling.update(Vec3(5.0f, 1.5f, 0.0f), false));
}

class SealedLightsRender : public ::testing::TestWithParam<tracer::BackendKind> {};

TEST_P(SealedLightsRender, CullingEqualsTheSceneWithoutThoseEmitters) {
    // Leaving the panels out of the light sampler is exactly the scene whose panels do not
    // emit: same light choices, same paths, the same image bit for bit.
    const SceneModel scene = make_sealed_lights_scene();
    SceneModel dark = scene;
    for (std::size_t i = 0; i < dark.instances.size(); ++i)
        if (is_panel(dark, i))
            dark.materials[std::size_t(dark.meshes[std::size_t(dark.instances[i].mesh)].material)]
                .emissive_factor = Rgb(0.0f);
    test::RenderRequest r;
    r.width = 32;
    r.height = 20;
    r.spp = 4;
    r.backend = GetParam();
    const FloatImage culled = test::render(scene, r);
    const FloatImage without = test::render(dark, r);
    ASSERT_EQ(culled.rgb.size(), without.rgb.size());
    EXPECT_EQ(std::memcmp(culled.rgb.data(), without.rgb.data(), culled.rgb.size() * sizeof(float)),
              0);
    r.integrator.cull_sealed_lights = false;
    const FloatImage all_lights = test::render(scene, r);
    EXPECT_NE(
        std::memcmp(culled.rgb.data(), all_lights.rgb.data(), culled.rgb.size() * sizeof(float)), 0)
        << "not culling samples the panels too";
}

TEST_P(SealedLightsRender, CullingAgreesStatisticallyWithSamplingEveryEmitter) {
    const SceneModel scene = make_sealed_lights_scene();
    std::vector<FloatImage> culled, all;
    for (int b = 0; b < 16; ++b) {
        test::RenderRequest r;
        r.width = 24;
        r.height = 16;
        r.spp = 16;
        r.backend = GetParam();
        r.seed = 300 + uint32_t(b);
        culled.push_back(test::render(scene, r));
        r.seed = 400 + uint32_t(b);
        r.integrator.cull_sealed_lights = false;
        all.push_back(test::render(scene, r));
    }
    const auto result = test::compare_batches(culled, all, 0.01, 2);
    EXPECT_TRUE(result.agree(0.01)) << "min pixel p " << result.min_pixel_p << " (threshold "
                                    << result.pixel_threshold << "), mean p " << result.mean_p;
}

INSTANTIATE_TEST_SUITE_P(Backends, SealedLightsRender, ::testing::ValuesIn(test::built_backends()),
                         test::BackendTestName());

}  // namespace
}  // namespace pathfarm
