// BVH commit ops: a replica that asked for BVH nodes holds exactly the coordinator's BVH data
// after every commit; unchanged structures cost nothing; replicas that did not ask get none.
#include "coordinator/commit/bvh_ops.h"

#include <gtest/gtest.h>

#include "common/commit/commit_codec.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/scene_loader.h"
#include "coordinator/commit/commit_builder.h"
#include "coordinator/scene_graph/scene_graph.h"
#include "tests/support/commit_wire.h"
#include "tests/support/test_env.h"

namespace pathfarm::coord {
namespace {

TEST(BvhOps, ReplicaHoldsTheCoordinatorsBvhEveryFrame) {
    PF_REQUIRE_SCENES(scenes);
    auto loaded = load_scene(scenes + "/cesium-man/CesiumMan.gltf");
    ASSERT_TRUE(loaded.ok());
    SceneGraph graph(*loaded);
    AccelUpdater accel;
    auto snap = accel.build(graph.state(), 0);
    Commit first = make_snapshot(graph.state(), 0);
    for (CommitOp& op : build_bvh_ops(nullptr, *snap))
        first.ops.push_back(std::move(op));
    ReplicaState replica;
    ASSERT_TRUE(apply_commit(replica, test::through_wire(first)).ok());
    EXPECT_EQ(bvh_hash(replica.bvh), bvh_hash(derived_bvh(*snap)));
    for (uint64_t f = 1; f <= 15; ++f) {
        graph.advance(double(f) / 10.0);
        const ChangeSet changes = graph.take_changes();
        const auto previous = snap;
        snap = accel.update(graph.state(), changes, f);
        Commit c = build_commit(graph.state(), changes, f, f - 1);
        const auto bvh_ops = build_bvh_ops(previous.get(), *snap);
        EXPECT_FALSE(bvh_ops.empty()) << "the skinned mesh's BVH is refitted every frame";
        for (const CommitOp& op : bvh_ops)
            c.ops.push_back(op);
        ASSERT_TRUE(apply_commit(replica, test::through_wire(c)).ok());
        ASSERT_EQ(bvh_hash(replica.bvh), bvh_hash(derived_bvh(*snap))) << "frame " << f;
        ASSERT_EQ(content_hash(replica.scene), content_hash(graph.state()));
    }
}

TEST(BvhOps, UnchangedStructuresSendNothing) {
    SceneGraph graph(make_default_scene());
    AccelUpdater accel;
    const auto a = accel.build(graph.state(), 0);
    graph.advance(1.0);
    const auto b = accel.update(graph.state(), graph.take_changes(), 1);
    EXPECT_TRUE(build_bvh_ops(a.get(), *b).empty());
    EXPECT_FALSE(build_bvh_ops(nullptr, *b).empty());
}

}  // namespace
}  // namespace pathfarm::coord
