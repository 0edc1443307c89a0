// Free camera with collisions.
#include "coordinator/game/free_camera.h"

#include <spdlog/spdlog.h>

#include "common/math/transform.h"
#include "coordinator/scene_graph/scene_graph.h"

namespace pathfarm::coord {
namespace {

constexpr float kMaxPitch = 1.5f;  // just short of straight up or down

std::optional<Camera> active_camera(const SceneState& s) {
    const auto it = s.cameras.find(s.active_camera);
    if (it == s.cameras.end()) return std::nullopt;
    return it->second;
}

}  // namespace

FreeCameraGame::FreeCameraGame(const SceneGraph& graph) {
    const Camera cam = active_camera(graph.state()).value_or(Camera{});
    has_camera_ = active_camera(graph.state()).has_value();
    yfov_ = cam.yfov_radians;
    take_pose(cam.camera_to_world);
}

void FreeCameraGame::take_pose(const Mat4& camera_to_world) {
    eye_ = transform_point(camera_to_world, Vec3(0.0f));
    const Vec3 forward = glm::normalize(transform_vector(camera_to_world, Vec3(0, 0, -1)));
    // Straight down (or up) the view has no heading of its own: the image's top gives it
    // (ahead when looking down, behind when looking up). The pitch stops short of vertical as
    // turning does: a vertical view with +Y up has no image up (look_at_camera).
    Vec3 heading = forward;
    if (forward.x * forward.x + forward.z * forward.z < 1e-6f) {
        const Vec3 top = transform_vector(camera_to_world, Vec3(0, 1, 0));
        heading = forward.y < 0.0f ? top : -top;
    }
    yaw_ = std::atan2(-heading.x, -heading.z);
    pitch_ = std::clamp(std::asin(std::clamp(forward.y, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
}

Vec3 FreeCameraGame::view_direction() const {
    return {-std::sin(yaw_) * std::cos(pitch_), std::sin(pitch_),
            -std::cos(yaw_) * std::cos(pitch_)};
}

void FreeCameraGame::publish_camera(SceneGraph& graph) const {
    Camera cam = active_camera(graph.state()).value_or(Camera{});
    cam.yfov_radians = yfov_;
    cam.camera_to_world = look_at_camera(eye_, eye_ + view_direction(), Vec3(0, 1, 0));
    graph.set_camera(has_camera_ ? std::optional(graph.state().active_camera) : std::nullopt, cam,
                     true);
}

Vec3 FreeCameraGame::collide(const Vec3& from, const Vec3& move,
                             const RayQueryService& queries) const {
    Vec3 remaining = move;
    Vec3 at = from;
    for (int slide = 0; slide < 3; ++slide) {  // move, then slide along what stopped us
        const float length = glm::length(remaining);
        if (!(length > 1e-6f)) break;
        const Vec3 dir = remaining / length;
        Ray ray{at, dir, length + 4.0f * kBodyRadius};  // glancing approaches stop earlier
        const auto hit = queries.closest_hit(ray);
        if (!hit) return at + remaining;
        // Stop where the distance to the surface's plane, not along the ray, is the radius.
        const Vec3 n = glm::dot(hit->normal, dir) > 0.0f ? -hit->normal : hit->normal;
        const float approach = std::max(-glm::dot(dir, n), 1e-3f);
        const float allowed = std::max(0.0f, hit->distance - kBodyRadius / approach);
        at += dir * allowed;
        // What is left, without its part into the surface.
        remaining = dir * (length - allowed);
        remaining -= glm::dot(remaining, n) * n;
    }
    return at;
}

void FreeCameraGame::on_input(const PlayerInput& in, double clock_seconds, SceneGraph& graph,
                              const RayQueryService& queries) {
    if (in.camera_to_world) {  // an absolute pose: scripted clients place the camera themselves
        const Mat4& m = *in.camera_to_world;
        take_pose(m);
        Camera cam = active_camera(graph.state()).value_or(Camera{});
        cam.camera_to_world = m;
        graph.set_camera(has_camera_ ? std::optional(graph.state().active_camera) : std::nullopt,
                         cam, true);
    }
    const auto& mv = in.move;
    if (mv[3] != 0.0f || mv[4] != 0.0f) {
        yaw_ = std::remainder(yaw_ + mv[3], 2.0f * float(M_PI));
        pitch_ = std::clamp(pitch_ + mv[4], -kMaxPitch, kMaxPitch);
    }
    const Vec3 forward(-std::sin(yaw_), 0.0f, -std::cos(yaw_));
    const Vec3 right(std::cos(yaw_), 0.0f, -std::sin(yaw_));
    const Vec3 step = mv[0] * right + Vec3(0.0f, mv[1], 0.0f) + mv[2] * forward;
    if (glm::length(step) > 0.0f) eye_ = collide(eye_, step, queries);
    if (glm::length(step) > 0.0f || mv[3] != 0.0f || mv[4] != 0.0f) publish_camera(graph);
    if (in.action) {
        const auto hit = queries.closest_hit(Ray{eye_, view_direction(), 1e30f});
        if (hit) on_action(*hit, clock_seconds, graph);
    }
}

void FreeCameraGame::on_action(const RayQueryHit& hit, double, SceneGraph&) {
    spdlog::info("action: the crosshair is on instance {} at {:.2f} m", hit.instance, hit.distance);
}

}  // namespace pathfarm::coord
