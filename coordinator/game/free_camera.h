// The player's camera: walks and looks around, and cannot pass through geometry: a ray along
// each step (the coordinator's ray queries) finds what is ahead, the eye stops kBodyRadius
// from its plane and slides along it. Thin gaps off the ray's line are not checked (a body
// sweep would be). The action key reports what the crosshair hits.
#pragma once

#include "coordinator/game/game.h"
#include "coordinator/query/ray_query.h"

namespace pathfarm::coord {

class FreeCameraGame : public Game {
public:
    static constexpr float kBodyRadius = 0.25f;

    explicit FreeCameraGame(const SceneGraph& graph);
    void on_input(const PlayerInput& input, double clock_seconds, SceneGraph& graph,
                  const RayQueryService& queries) override;
    void update(double, SceneGraph&) override {}
    std::string name() const override { return "free-camera"; }

    Vec3 eye() const { return eye_; }
    Vec3 view_direction() const;

protected:
    // The crosshair's hit when the action key was pressed (nothing by default).
    virtual void on_action(const RayQueryHit& hit, double clock_seconds, SceneGraph& graph);

private:
    void take_pose(const Mat4& camera_to_world);  // eye, yaw and pitch from a camera matrix
    Vec3 collide(const Vec3& from, const Vec3& move, const RayQueryService& queries) const;
    void publish_camera(SceneGraph& graph) const;

    Vec3 eye_{0.0f};
    float yaw_ = 0.0f, pitch_ = 0.0f;  // radians; yaw 0 looks down -Z
    float yfov_ = 0.0f;
    bool has_camera_ = false;
};

}  // namespace pathfarm::coord
