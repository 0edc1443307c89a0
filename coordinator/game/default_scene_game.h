// builtin:default's game: a gold ball rolls to and fro, the spot panel switches on and off on
// a timer, and the action key opens or closes the door and switches the lamp when the
// crosshair is on them. Every path of the frame loop runs: rigid animation, light edits,
// camera input and ray queries.
#pragma once

#include "coordinator/game/free_camera.h"

namespace pathfarm::coord {

class DefaultSceneGame : public FreeCameraGame {
public:
    static constexpr double kDoorSwingSeconds = 1.0;
    static constexpr double kSpotPeriodSeconds = 4.0;  // on for 3 s, off for 1 s

    static Result<std::unique_ptr<DefaultSceneGame>> create(const SceneGraph& graph);

    void update(double clock_seconds, SceneGraph& graph) override;
    std::string name() const override { return "default"; }

    bool door_open() const { return door_open_; }
    bool lamp_on() const { return lamp_on_; }

protected:
    void on_action(const RayQueryHit& hit, double clock_seconds, SceneGraph& graph) override;

private:
    explicit DefaultSceneGame(const SceneGraph& graph) : FreeCameraGame(graph) {}
    float door_angle(double clock_seconds) const;

    uint32_t ball_ = 0, door_ = 0;
    std::vector<uint32_t> lamp_nodes_;
    uint32_t spot_material_ = 0, lamp_material_ = 0;
    Rgb spot_colour_{0.0f}, lamp_colour_{0.0f};
    bool door_open_ = false, lamp_on_ = true, lamp_dirty_ = false;
    std::optional<bool> spot_on_;  // as last sent
    double door_since_ = -1e9;     // game time of the last door toggle
};

}  // namespace pathfarm::coord
