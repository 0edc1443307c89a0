// Skinning and morph targets against hand-computed poses of the sample models.
#include "coordinator/animation/skinning.h"

#include <gtest/gtest.h>

#include "common/math/transform.h"
#include "common/scene/load/scene_loader.h"
#include "coordinator/animation/animator.h"
#include "tests/support/test_env.h"

namespace pathfarm::coord {
namespace {

// World matrix of a node by walking its parents, written independently of the code under test.
Mat4 world_of(const SceneModel& s, int node) {
    Mat4 m = compose_trs(s.nodes[node].translation, s.nodes[node].rotation, s.nodes[node].scale);
    if (!s.nodes[node].has_trs) m = s.nodes[node].local;
    return s.nodes[node].parent >= 0 ? world_of(s, s.nodes[node].parent) * m : m;
}

TEST(Skinning, RiggedSimplePoseMatchesHandComputation) {
    PF_REQUIRE_SCENES(scenes);
    auto loaded = load_scene(scenes + "/rigged-simple/RiggedSimple.gltf");
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    ASSERT_EQ(loaded->skins.size(), 1u);
    for (float t : {0.0f, 0.6f, 1.3f, 2.0f}) {
        SceneModel scene = *loaded;
        apply_clip(scene, 0, t);
        const SceneModel posed = pose_scene(scene);
        int skinned_instances = 0;
        for (std::size_t i = 0; i < scene.instances.size(); ++i) {
            const Instance& inst = scene.instances[i];
            if (scene.nodes[inst.node].skin < 0) continue;
            ++skinned_instances;
            const Mesh& base = scene.meshes[inst.mesh];
            const Mesh& got = posed.meshes[posed.instances[i].mesh];
            EXPECT_EQ(posed.instances[i].transform, Mat4(1.0f))
                << "skinned output is in world space";
            const Skin& skin = scene.skins[scene.nodes[inst.node].skin];
            for (std::size_t v = 0; v < base.positions.size(); v += 7) {
                Vec4 p(0.0f);
                const Vec4 w = base.weights[v];
                const float sum = w.x + w.y + w.z + w.w;
                for (int k = 0; k < 4; ++k) {
                    const int j = base.joints[v][k];
                    p += (w[k] / sum) * (world_of(scene, skin.joints[j]) * skin.inverse_bind[j] *
                                         Vec4(base.positions[v], 1.0f));
                }
                EXPECT_NEAR(glm::distance(Vec3(p), got.positions[v]), 0.0f, 1e-4f)
                    << "t=" << t << " v=" << v;
            }
        }
        EXPECT_EQ(skinned_instances, 1);
    }
}

TEST(Skinning, MorphWeightsAddTargetDeltas) {
    PF_REQUIRE_SCENES(scenes);
    auto loaded = load_scene(scenes + "/animated-morph-cube/AnimatedMorphCube.gltf");
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    SceneModel scene = *loaded;
    const Instance inst = scene.instances.at(0);
    const Mesh& base = scene.meshes[inst.mesh];
    ASSERT_EQ(base.morph_targets.size(), 2u);
    scene.nodes[inst.node].morph_weights = {0.25f, 0.5f};
    const Mesh posed = deform_instance(scene, inst, node_world_transforms(scene));
    for (std::size_t v = 0; v < base.positions.size(); ++v) {
        const Vec3 want = base.positions[v] + 0.25f * base.morph_targets[0].positions[v] +
                          0.5f * base.morph_targets[1].positions[v];
        EXPECT_NEAR(glm::distance(posed.positions[v], want), 0.0f, 1e-6f);
    }
}

TEST(Skinning, SkinnedModelsLoadAndPoseEveryClip) {
    PF_REQUIRE_SCENES(scenes);
    for (const char* file :
         {"fox/Fox.glb", "cesium-man/CesiumMan.gltf", "rigged-figure/RiggedFigure.gltf",
          "simple-skin/SimpleSkin.gltf", "box-animated/BoxAnimated.gltf"}) {
        auto loaded = load_scene(scenes + "/" + file);
        ASSERT_TRUE(loaded.ok()) << loaded.error().message;
        ASSERT_FALSE(loaded->animations.empty()) << file;
        for (std::size_t c = 0; c < loaded->animations.size(); ++c) {
            SceneModel scene = *loaded;
            const AnimationClip& clip = scene.animations[c];
            apply_clip(scene, int(c), 0.5f * (clip.start_time + clip.end_time));
            const SceneModel posed = pose_scene(scene);
            for (const Mesh& m : posed.meshes)
                for (const Vec3& p : m.positions)
                    ASSERT_TRUE(is_finite(p)) << file;
        }
    }
}

}  // namespace
}  // namespace pathfarm::coord
