// builtin:default's game through the real scene graph, BVH and ray queries: collisions stop
// the camera at walls, the action key opens the door and switches the lamp only when the
// crosshair is on them, and time moves the ball and switches the spot light.
#include <cmath>

#include <gtest/gtest.h>

#include "common/math/transform.h"
#include "common/scene/load/builtin_scenes.h"
#include "coordinator/accel/accel_updater.h"
#include "coordinator/game/default_scene_game.h"
#include "coordinator/query/ray_query.h"
#include "coordinator/scene_graph/scene_graph.h"

namespace pathfarm::coord {
namespace {

struct World {
    SceneGraph graph{make_default_scene()};
    AccelUpdater accel;
    RayQueryService queries;
    std::unique_ptr<Game> game;

    World() {
        auto g = make_game("auto", "builtin:default", graph);
        EXPECT_TRUE(g.ok());
        game = std::move(*g);
        publish();
    }
    void publish() {
        graph.advance(0.0);
        graph.take_changes();
        queries.publish(accel.build(graph.state(), 0));
    }
    Vec3 eye() const {
        return transform_point(
            graph.state().cameras.at(graph.state().active_camera).camera_to_world, Vec3(0.0f));
    }
    void look(Vec3 from, Vec3 at) {
        PlayerInput in;
        in.camera_to_world = look_at_camera(from, at, Vec3(0, 1, 0));
        game->on_input(in, 0.0, graph, queries);
    }
    void act(double t) {
        PlayerInput in;
        in.action = true;
        game->on_input(in, t, graph, queries);
    }
    Mat4 node_world(const std::string& name) const {
        const auto node = graph.find_nodes(name).at(0);
        for (const auto& [id, inst] : graph.state().instances)
            if (graph.node_of_instance(id) == node) return inst.transform;
        ADD_FAILURE() << name << " has no instance";
        return Mat4(1.0f);
    }
    Rgb emission(const std::string& material) const {
        return graph.state().materials.at(*graph.find_material(material)).emissive_factor;
    }
};

TEST(DefaultSceneGame, WalkingIntoAWallStopsABodyRadiusShortOfIt) {
    World w;
    w.look({0.0f, 1.5f, -1.0f}, {0.0f, 1.5f, -5.0f});  // facing the back wall (z = -8)
    for (int i = 0; i < 40; ++i) {                     // 20 m forward in half-metre steps
        PlayerInput in;
        in.move[2] = 0.5f;
        w.game->on_input(in, 0.0, w.graph, w.queries);
    }
    const Vec3 e = w.eye();
    // The door stands 6 cm in front of the back wall; nothing else is in the way at x = 0.
    EXPECT_GE(e.z, -8.0f + FreeCameraGame::kBodyRadius - 1e-3f);
    EXPECT_LE(e.z, -8.0f + FreeCameraGame::kBodyRadius + 0.05f);
    EXPECT_NEAR(e.x, 0.0f, 1e-4f);
    EXPECT_NEAR(e.y, 1.5f, 1e-4f);
}

// A camera looking straight down (or up) with the world's +Y as up had no image up: its
// matrix was NaN, and so was every frame after the player moved. It walks towards the image's
// top (behind it looking up), and every published camera is finite.
TEST(DefaultSceneGame, AVerticalViewWalksTowardsTheImagesTopWithAFiniteCamera) {
    for (const float down : {-1.0f, 1.0f}) {
        World w;
        const Vec3 from(0.0f, 1.5f, -1.0f);
        w.look(from, from + Vec3(0.0f, down, 0.0f));
        const auto camera = [&] {
            return w.graph.state().cameras.at(w.graph.state().active_camera).camera_to_world;
        };
        const Vec3 top = glm::normalize(transform_vector(camera(), Vec3(0, 1, 0)));
        PlayerInput in;
        in.move[2] = 0.2f;
        w.game->on_input(in, 0.0, w.graph, w.queries);
        const Mat4 m = camera();
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                ASSERT_TRUE(std::isfinite(m[c][r])) << down << " " << c << " " << r;
        const Vec3 view = glm::normalize(transform_vector(m, Vec3(0, 0, -1)));
        EXPECT_GT(view.y * down, 0.99f) << "still looking nearly straight " << down;
        const Vec3 ahead = down < 0.0f ? top : -top;
        const Vec3 moved = w.eye() - from;
        EXPECT_NEAR(glm::dot(moved, ahead), 0.2f, 1e-4f) << down;
        EXPECT_NEAR(glm::length(moved), 0.2f, 1e-4f) << down;
    }
}

TEST(DefaultSceneGame, WalkingAlongAWallSlides) {
    World w;
    w.look({-3.5f, 1.5f, -1.0f}, {-4.0f, 1.5f, -1.5f});  // facing the left wall at 45 degrees
    for (int i = 0; i < 10; ++i) {
        PlayerInput in;
        in.move[2] = 0.3f;
        w.game->on_input(in, 0.0, w.graph, w.queries);
    }
    EXPECT_GE(w.eye().x, -4.0f + FreeCameraGame::kBodyRadius - 1e-3f);
    EXPECT_LT(w.eye().z, -2.0f);  // it kept moving along the wall
}

TEST(DefaultSceneGame, ActionOpensTheDoorOnlyWhenAimedAtIt) {
    World w;
    auto* game = dynamic_cast<DefaultSceneGame*>(w.game.get());
    ASSERT_NE(game, nullptr);
    const Mat4 closed = w.node_world("door");
    w.look({0.0f, 1.5f, -3.0f}, {-3.0f, 1.5f, -3.0f});  // at the left wall, not the door
    w.act(1.0);
    EXPECT_FALSE(game->door_open());
    w.look({1.35f, 1.2f, -5.0f}, {1.35f, 1.0f, -7.9f});  // at the door
    w.act(1.0);
    EXPECT_TRUE(game->door_open());
    game->update(1.0 + DefaultSceneGame::kDoorSwingSeconds, w.graph);
    w.graph.advance(2.0);
    const Mat4 open = w.node_world("door");
    EXPECT_GT(glm::length(Vec3(open[3]) - Vec3(closed[3])), 0.3f);  // the panel swung out
    // The door's world transform is the scene's own hinge function at the open angle.
    const Mat4 expected = default_scene_door_transform(1.75f);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(open[c][r], expected[c][r], 1e-4f);
}

TEST(DefaultSceneGame, ActionOnTheLampSwitchesIt) {
    World w;
    auto* game = dynamic_cast<DefaultSceneGame*>(w.game.get());
    const Rgb on = w.emission("lamp-bulb");
    ASSERT_GT(on.x, 0.0f);
    w.look({-3.0f, 1.2f, -4.5f}, {-3.0f, 0.6f, -6.8f});  // at the lamp stand
    w.act(0.5);
    game->update(0.5, w.graph);
    EXPECT_FALSE(game->lamp_on());
    EXPECT_EQ(w.emission("lamp-bulb"), Rgb(0.0f));
    EXPECT_TRUE(w.graph.take_changes().materials_set.count(*w.graph.find_material("lamp-bulb")));
    w.act(0.6);
    game->update(0.6, w.graph);
    EXPECT_EQ(w.emission("lamp-bulb"), on);
}

TEST(DefaultSceneGame, TimeMovesTheBallAndSwitchesTheSpotLight) {
    World w;
    w.game->update(0.0, w.graph);
    w.graph.advance(0.0);
    const Mat4 ball0 = w.node_world("gold-ball");
    const Rgb spot_on = w.emission("spot-panel");
    EXPECT_GT(spot_on.x, 0.0f);
    w.graph.take_changes();
    w.game->update(1.0, w.graph);
    w.graph.advance(1.0);
    EXPECT_NE(w.node_world("gold-ball"), ball0);
    EXPECT_TRUE(w.graph.take_changes().materials_set.empty());  // unchanged light: no edit
    w.game->update(3.5, w.graph);  // the last second of each 4 s period is dark
    EXPECT_EQ(w.emission("spot-panel"), Rgb(0.0f));
    w.game->update(4.2, w.graph);
    EXPECT_EQ(w.emission("spot-panel"), spot_on);
}

TEST(DefaultSceneGame, RefusesOtherScenesAndUnknownKinds) {
    SceneGraph cornell(make_cornell_box());
    EXPECT_FALSE(make_game("default", "builtin:cornell", cornell).ok());
    EXPECT_EQ(make_game("auto", "builtin:cornell", cornell).value()->name(), "free-camera");
    EXPECT_FALSE(make_game("chess", "builtin:cornell", cornell).ok());
}

}  // namespace
}  // namespace pathfarm::coord
