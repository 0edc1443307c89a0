// Dynamic instances (Instance::dynamic): the coordinator's scene graph marks an instance that
// moved after it was placed, and keeps the mark; a tracer's Embree scene then instances its
// mesh instead of baking it, so moving it again is a top-level commit, not a build of every
// baked triangle (builtin:default's door: a mesh placed once).
#include <optional>
#include <string>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/scene/load/builtin_scenes.h"
#include "common/scene/scene_state.h"
#include "coordinator/scene_graph/scene_graph.h"
#include "tracer-node/backend/render_backend.h"
#include "tracer-node/embree/embree_scene.h"

namespace pathfarm {
namespace {

using coord::ChangeSet;
using coord::SceneGraph;

uint32_t node_named(const SceneModel& scene, const std::string& name) {
    for (std::size_t n = 0; n < scene.nodes.size(); ++n)
        if (scene.nodes[n].name == name) return uint32_t(n);
    ADD_FAILURE() << "no node " << name;
    return 0;
}

int dynamic_count(const SceneState& s) {
    int count = 0;
    for (const auto& [id, inst] : s.instances)
        count += inst.dynamic ? 1 : 0;
    return count;
}

TEST(DynamicInstances, TheSceneGraphMarksWhatMovedAfterItWasPlacedAndKeepsIt) {
    const SceneModel scene = make_default_scene();
    SceneGraph graph(scene);
    graph.advance(0.0);
    (void)graph.take_changes();
    EXPECT_EQ(dynamic_count(graph.state()), 0) << "placing is not moving";
    const uint32_t door = node_named(scene, "door");
    ASSERT_TRUE(graph
                    .set_node_transform(door, scene.nodes[door].local *
                                                  glm::rotate(Mat4(1.0f), 0.3f, Vec3(0, 1, 0)))
                    .ok());
    graph.advance(0.1);
    const ChangeSet moved = graph.take_changes();
    ASSERT_EQ(moved.instances_set.size(), 1u);
    const uint32_t id = *moved.instances_set.begin();
    EXPECT_TRUE(graph.state().instances.at(id).dynamic);
    EXPECT_EQ(dynamic_count(graph.state()), 1);
    graph.advance(0.2);  // still: the mark stays (a late replica lays out the same)
    EXPECT_TRUE(graph.state().instances.at(id).dynamic);
}

// The door moved twice: once (frame 1) it becomes dynamic, a new layout; then (frame 2) the
// update must be a placement alone. Without the mark the same move re-bakes.
std::optional<tracer::EmbreeUpdate> second_move(bool mark_dynamic) {
    SceneModel scene = make_default_scene();
    const uint32_t door = node_named(scene, "door");
    Instance* inst = nullptr;
    for (Instance& i : scene.instances)
        if (i.node == int(door)) inst = &i;
    EXPECT_NE(inst, nullptr);
    if (!inst) return std::nullopt;
    inst->dynamic = mark_dynamic;
    auto built = tracer::EmbreeScene::build(scene, 2);
    EXPECT_TRUE(built.ok()) << built.error().message;
    if (!built.ok()) return std::nullopt;
    const SceneModel before = scene;
    inst->transform = glm::translate(Mat4(1.0f), Vec3(0.0f, 0.0f, 0.1f)) * inst->transform;
    const tracer::SceneChanges changes = tracer::diff_scenes(before, scene);
    EXPECT_FALSE(changes.structure);
    auto update = (*built)->update(scene, changes);
    EXPECT_TRUE(update.ok()) << update.error().message;
    if (!update.ok()) return std::nullopt;
    return *update;
}

TEST(DynamicInstances, MovingADynamicMeshPlacedOnceIsATopLevelCommit) {
    const auto dynamic = second_move(true);
    ASSERT_TRUE(dynamic.has_value());
    EXPECT_EQ(dynamic->instances_placed, 1);
    EXPECT_EQ(dynamic->instances_rebaked, 0);
    EXPECT_FALSE(dynamic->baked_rebuilt);
    const auto baked = second_move(false);
    ASSERT_TRUE(baked.has_value());
    EXPECT_EQ(baked->instances_rebaked, 1);
    EXPECT_TRUE(baked->baked_rebuilt);
}

}  // namespace
}  // namespace pathfarm
