// A backend updated frame after frame by what changed renders the same bits as one given each
// frame's scene anew: camera moves within and across recentring cells, moved instances of
// shared and of single meshes, animation and skinning. This is what keeps late-joining
// tracers and pathfarm-render bit-identical to a tracer with a long history
// (docs/determinism.md), and it exercises every update path of the Embree scene.
#include <cstring>
#include <functional>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/scene_loader.h"
#include "coordinator/animation/animator.h"
#include "coordinator/animation/skinning.h"
#include "tests/support/render_helpers.h"
#include "tests/support/test_env.h"

namespace pathfarm::incremental_update_test {
namespace {

using tracer::BackendKind;

// Frame f of a sequence: the scene in world space, as a replica holds it.
using Sequence = std::function<SceneModel(int frame)>;

FrameSpec frame_spec(const SceneModel& scene, int f) {
    return FrameSpec{24, 24, uint32_t(f), 3, 2, 0, scene.cameras.at(0)};
}

std::vector<float> render_rows(tracer::RenderBackend& backend, const SceneModel& scene, int f) {
    tracer::RenderJob job{frame_spec(scene, f), IntegratorSettings{}, 0, 24, {}};
    std::vector<float> rgb(24 * 24 * 3);
    auto stats = backend.render_rows(job, rgb.data());
    EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
    return rgb;
}

// Renders `frames` frames of `sequence` through one backend updated by diffs and through a
// fresh backend per frame; expects the same bits every frame.
void expect_updates_match_rebuilds(const Sequence& sequence, int frames, BackendKind kind) {
    auto updated = tracer::create_backend(kind, tracer::BackendOptions{2, 0, 0});
    ASSERT_TRUE(updated.ok()) << updated.error().message;
    tracer::SceneStepper steps;  // its scene() is the model the updated backend refers to
    for (int f = 0; f < frames; ++f) {
        const tracer::SceneChanges changes = steps.step(sequence(f));
        const SceneModel& current = steps.scene();
        ASSERT_TRUE((*updated)->update_scene(current, changes).ok()) << "frame " << f;
        SceneModel fresh_scene = steps.world();
        recentre_on_camera(fresh_scene, fresh_scene.cameras.at(0));
        auto fresh = tracer::create_backend(kind, tracer::BackendOptions{2, 0, 0});
        ASSERT_TRUE(fresh.ok());
        ASSERT_TRUE((*fresh)->set_scene(fresh_scene).ok());
        const std::vector<float> a = render_rows(**updated, current, f);
        const std::vector<float> b = render_rows(**fresh, fresh_scene, f);
        ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0)
            << "frame " << f << ": the updated backend's image differs from a fresh build";
    }
}

// Moves the camera by `step` (in cells) per frame from the scene's first camera.
SceneModel with_camera_moved(SceneModel scene, double cells) {
    if (scene.cameras.empty()) scene.cameras.push_back(frame_bounds(world_bounds(scene), 1.0f));
    const double cell = recentre_cell(world_bounds(scene));
    scene.cameras[0].camera_to_world =
        glm::translate(Mat4(1.0f), Vec3(float(cells * cell), 0.0f, float(0.2 * cells * cell))) *
        scene.cameras[0].camera_to_world;
    return scene;
}

// Moves every instance of the node called `name` by `by`; returns how many moved.
int translate_named(SceneModel& s, const std::string& name, const Vec3& by) {
    int moved = 0;
    for (Instance& inst : s.instances)
        if (inst.node >= 0 && s.nodes[std::size_t(inst.node)].name == name) {
            inst.transform = glm::translate(Mat4(1.0f), by) * inst.transform;
            ++moved;
        }
    return moved;
}

class IncrementalUpdate : public ::testing::TestWithParam<BackendKind> {};

TEST_P(IncrementalUpdate, CameraWithinAndAcrossCellsAndMovedObjects) {
    const SceneModel base = make_default_scene();
    expect_updates_match_rebuilds(
        [&](int f) {
            SceneModel s = with_camera_moved(base, 0.3 * f);  // crosses a cell every ~3 frames
            // Two instances of a shared mesh and one of a single mesh move.
            const Vec3 by(0.05f * float(f), 0.0f, 0.0f);
            EXPECT_EQ(translate_named(s, "gold-ball", by), 2);
            EXPECT_EQ(translate_named(s, "glass-ball", by), 1);
            return s;
        },
        7, GetParam());
}

// Only the instances of a shared mesh move: a top-level commit alone must show them.
TEST_P(IncrementalUpdate, InstancesOfASharedMeshAlone) {
    const SceneModel base = make_default_scene();
    expect_updates_match_rebuilds(
        [&](int f) {
            SceneModel s = base;
            translate_named(s, "gold-ball", Vec3(0.0f, 0.1f * float(f), 0.0f));
            return s;
        },
        3, GetParam());
}

// Dynamic instances of single meshes (Instance::dynamic): the door and the glass ball become
// dynamic at frame 1, as the coordinator marks what moved (a new layout), then move and
// deform as instances; the bits stay a fresh build's throughout.
TEST_P(IncrementalUpdate, SingleMeshesBecomingDynamic) {
    const SceneModel base = make_default_scene();
    expect_updates_match_rebuilds(
        [&](int f) {
            SceneModel s = base;
            EXPECT_EQ(translate_named(s, "glass-ball", Vec3(0.0f, 0.0f, 0.04f * float(f))), 1);
            EXPECT_EQ(translate_named(s, "door", Vec3(0.03f * float(f), 0.0f, 0.0f)), 1);
            for (Instance& inst : s.instances) {
                const std::string& name = s.nodes[std::size_t(inst.node)].name;
                if (f > 0 && (name == "glass-ball" || name == "door")) inst.dynamic = true;
                if (f > 2 && name == "glass-ball")  // and then it deforms
                    for (Vec3& p : s.meshes[std::size_t(inst.mesh)].positions)
                        p *= 1.0f + 0.01f * float(f);
            }
            return s;
        },
        5, GetParam());
}

TEST_P(IncrementalUpdate, DeformedSharedAndSingleMeshes) {
    const SceneModel base = make_default_scene();
    expect_updates_match_rebuilds(
        [&](int f) {
            SceneModel s = base;
            for (Mesh& m : s.meshes)  // every mesh breathes: shared ones rebuilt, single re-baked
                for (Vec3& p : m.positions)
                    p *= 1.0f + 0.02f * float(f % 3);
            return s;
        },
        4, GetParam());
}

TEST_P(IncrementalUpdate, AnimatedAndSkinnedGltf) {
    PF_REQUIRE_SCENES(scenes);
    for (const char* file : {"box-animated/BoxAnimated.gltf", "cesium-man/CesiumMan.gltf"}) {
        auto loaded = load_scene(scenes + "/" + file);
        ASSERT_TRUE(loaded.ok()) << file << ": " << loaded.error().message;
        SCOPED_TRACE(file);
        expect_updates_match_rebuilds(
            [&](int f) {
                SceneModel s = *loaded;
                coord::apply_clip(s, 0, 0.15f * float(f));
                if (has_deformation(s)) s = coord::pose_scene(s);
                if (s.cameras.empty())
                    s.cameras.push_back(frame_bounds(world_bounds(*loaded), 1.0f));
                return s;
            },
            4, GetParam());
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, IncrementalUpdate, ::testing::ValuesIn(test::built_backends()),
                         test::BackendTestName());

}  // namespace
}  // namespace pathfarm::incremental_update_test
