// builtin:default's game logic.
#include "coordinator/game/default_scene_game.h"

#include <algorithm>

#include <spdlog/spdlog.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/math/transform.h"
#include "common/scene/load/builtin_scenes.h"
#include "coordinator/scene_graph/scene_graph.h"

namespace pathfarm::coord {
namespace {

constexpr float kDoorOpenRadians = 1.75f;  // about 100 degrees, into the room
constexpr float kBallRadius = 0.35f;
const Vec3 kBallHome(0.6f, 0.35f, -4.2f);

}  // namespace

Result<std::unique_ptr<DefaultSceneGame>> DefaultSceneGame::create(const SceneGraph& graph) {
    std::unique_ptr<DefaultSceneGame> g(new DefaultSceneGame(graph));
    const auto balls = graph.find_nodes("gold-ball");
    const auto doors = graph.find_nodes("door");
    g->lamp_nodes_ = graph.find_nodes("lamp");
    for (uint32_t n : graph.find_nodes("lamp-stand"))
        g->lamp_nodes_.push_back(n);
    const auto spot = graph.find_material("spot-panel");
    const auto lamp = graph.find_material("lamp-bulb");
    if (balls.empty() || doors.empty() || g->lamp_nodes_.empty() || !spot || !lamp)
        return make_error(ErrorCode::invalid_argument,
                          "--game default: the scene is not builtin:default (no gold-ball, door, "
                          "lamp or spot-panel)");
    g->ball_ = balls.front();
    g->door_ = doors.front();
    g->spot_material_ = *spot;
    g->lamp_material_ = *lamp;
    g->spot_colour_ = graph.state().materials.at(*spot).emissive_factor;
    g->lamp_colour_ = graph.state().materials.at(*lamp).emissive_factor;
    return g;
}

float DefaultSceneGame::door_angle(double t) const {
    const double s = std::clamp((t - door_since_) / kDoorSwingSeconds, 0.0, 1.0);
    const float eased = float(s * s * (3.0 - 2.0 * s));
    return kDoorOpenRadians * (door_open_ ? eased : 1.0f - eased);
}

void DefaultSceneGame::update(double t, SceneGraph& graph) {
    // The ball rolls along x without slipping: its turn is the distance over its radius.
    const float x = 0.7f * float(std::sin(0.8 * t));
    const Mat4 ball = glm::translate(Mat4(1.0f), kBallHome + Vec3(x, 0.0f, 0.0f)) *
                      glm::rotate(Mat4(1.0f), -x / kBallRadius, Vec3(0, 0, 1));
    (void)graph.set_node_transform(ball_, ball);
    if (t - door_since_ <= kDoorSwingSeconds + 0.5)  // moving (and one last settled pose)
        (void)graph.set_node_transform(door_, default_scene_door_transform(door_angle(t)));
    const bool spot_on = std::fmod(t, kSpotPeriodSeconds) < kSpotPeriodSeconds - 1.0;
    if (spot_on_ != spot_on) {  // edit the light only when it switches
        (void)graph.set_light(spot_material_, spot_colour_, 1.0f, spot_on);
        spot_on_ = spot_on;
    }
    if (lamp_dirty_) {
        (void)graph.set_light(lamp_material_, lamp_colour_, 1.0f, lamp_on_);
        lamp_dirty_ = false;
    }
}

void DefaultSceneGame::on_action(const RayQueryHit& hit, double t, SceneGraph& graph) {
    const auto node = graph.node_of_instance(hit.instance);
    if (node == door_) {
        // Reversing mid-swing continues from the current angle.
        const double progress = std::clamp((t - door_since_) / kDoorSwingSeconds, 0.0, 1.0);
        door_open_ = !door_open_;
        door_since_ = t - (1.0 - progress) * kDoorSwingSeconds;
        spdlog::info("action: door {}", door_open_ ? "opens" : "closes");
    } else if (node &&
               std::find(lamp_nodes_.begin(), lamp_nodes_.end(), *node) != lamp_nodes_.end()) {
        lamp_on_ = !lamp_on_;
        lamp_dirty_ = true;
        spdlog::info("action: lamp {}", lamp_on_ ? "on" : "off");
    } else {
        FreeCameraGame::on_action(hit, t, graph);
    }
}

}  // namespace pathfarm::coord
