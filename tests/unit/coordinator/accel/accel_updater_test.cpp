// The per-frame updater on an animated, skinned scene: snapshots answer ray queries exactly as
// a brute-force loop over every triangle does, deforming meshes are refitted, static ones kept.
#include "coordinator/accel/accel_updater.h"

#include <gtest/gtest.h>

#include "common/math/transform.h"
#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/scene_loader.h"
#include "coordinator/accel/bvh_traversal.h"
#include "coordinator/query/ray_query.h"
#include "coordinator/scene_graph/scene_graph.h"
#include "tests/support/test_env.h"

namespace pathfarm::coord {
namespace {

std::optional<float> brute_force(const SceneState& s, const Ray& ray) {
    std::optional<float> best;
    for (const auto& [id, inst] : s.instances) {
        const Mesh& m = s.meshes.at(inst.mesh);
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            float d, u, v;
            const Ray r{ray.o, ray.d, best ? *best : ray.tmax};
            if (intersect_triangle(transform_point(inst.transform, m.positions[m.indices[t]]),
                                   transform_point(inst.transform, m.positions[m.indices[t + 1]]),
                                   transform_point(inst.transform, m.positions[m.indices[t + 2]]),
                                   r, d, u, v))
                best = d;
        }
    }
    return best;
}

TEST(AccelUpdater, AnimatedSkinnedSceneMatchesBruteForce) {
    PF_REQUIRE_SCENES(scenes);
    auto loaded = load_scene(scenes + "/cesium-man/CesiumMan.gltf");
    ASSERT_TRUE(loaded.ok());
    SceneGraph graph(*loaded);
    AccelUpdater updater;
    updater.build(graph.state(), 0);
    const Bounds3f box = world_bounds(to_scene_model(graph.state()));
    Pcg32 rng(11);
    int refits = 0, hits = 0;
    for (int frame = 1; frame <= 12; ++frame) {
        graph.advance(frame / 10.0);
        const auto snap = updater.update(graph.state(), graph.take_changes(), uint64_t(frame));
        refits += updater.last_stats().refits;
        for (int r = 0; r < 300; ++r) {
            Ray ray;
            ray.o =
                box.center() + (Vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) *
                                   box.extent() * 1.5f;
            ray.d =
                glm::normalize(box.center() +
                               (Vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) *
                                   box.extent() * 0.5f -
                               ray.o);
            const auto expected = brute_force(graph.state(), ray);
            const auto got = closest_hit(*snap, ray);
            ASSERT_EQ(expected.has_value(), got.has_value()) << "frame " << frame << " ray " << r;
            if (!got) continue;
            ++hits;
            EXPECT_NEAR(got->distance, *expected, 1e-4f * std::max(1.0f, *expected));
            EXPECT_NEAR(glm::distance(got->point, ray.o + got->distance * ray.d), 0.0f, 1e-3f);
            EXPECT_EQ(any_hit(*snap, ray), true);
        }
    }
    EXPECT_GT(refits, 0) << "the skinned mesh is refitted";
    EXPECT_GT(hits, 500);
}

TEST(AccelUpdater, StaticSceneKeepsItsBvhsAndRebuildsTopOnlyForInstances) {
    SceneGraph graph(make_default_scene());
    AccelUpdater updater;
    const auto first = updater.build(graph.state(), 0);
    graph.advance(1.0);
    const auto second = updater.update(graph.state(), graph.take_changes(), 1);
    EXPECT_FALSE(updater.last_stats().top_rebuilt);
    EXPECT_EQ(updater.last_stats().builds, 0);
    EXPECT_EQ(first->meshes.begin()->second, second->meshes.begin()->second)
        << "shared, not copied";
    const uint32_t node = 0;
    ASSERT_TRUE(graph.set_node_transform(node, glm::translate(Mat4(1.0f), Vec3(0, 0.1f, 0))).ok());
    updater.update(graph.state(), graph.take_changes(), 2);
    EXPECT_TRUE(updater.last_stats().top_rebuilt);
    EXPECT_EQ(updater.last_stats().builds, 0) << "a rigid move rebuilds no mesh BVH";
}

TEST(RayQuery, CornellLineOfSightAndClosestHit) {
    SceneGraph graph(make_cornell_box());
    AccelUpdater updater;
    RayQueryService queries;
    queries.publish(updater.build(graph.state(), 0));
    // Straight down from just under the ceiling in the box's middle front: the floor at y = 0.
    const auto hit =
        queries.closest_hit(Ray{Vec3(0.278f, 0.54f, 0.05f), Vec3(0, -1, 0), kInfinity});
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->distance, 0.54f, 1e-5f);
    EXPECT_NEAR(hit->normal.y, 1.0f, 1e-5f);
    // The tall block stands between these two points; the short one does not block the second pair.
    EXPECT_FALSE(queries.line_of_sight(Vec3(0.369f, 0.2f, 0.05f), Vec3(0.369f, 0.2f, 0.55f)));
    EXPECT_TRUE(queries.line_of_sight(Vec3(0.05f, 0.45f, 0.05f), Vec3(0.5f, 0.45f, 0.5f)));
    EXPECT_EQ(queries.frame(), 0u);
}

}  // namespace
}  // namespace pathfarm::coord
