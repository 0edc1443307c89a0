// How a frame's surfaces moved since the last (the camera, moved, new and deformed instances)
// as the temporal accumulator's reprojection asks about them per pixel, and which pixels lie
// next to a moving instance.
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "common/math/transform.h"
#include "coordinator/converge/temporal_accumulator.h"

namespace pathfarm::coord {

// A deformed instance's vertices last frame and now, each with its object-to-world.
struct Deformation {
    const SurfaceVertices* before = nullptr;
    const SurfaceVertices* now = nullptr;
    Mat4 before_to_world{1.0f}, now_to_world{1.0f};

    // How far the point at barycentrics b of triangle `prim` moved since last frame, in world
    // space; false unless the triangle is the same in both frames' meshes.
    bool displacement(uint32_t prim, const Vec2& b, Vec3& moved) const {
        if (prim == FirstHit::kNone || before->indices.size() != now->indices.size() ||
            std::size_t(prim) * 3 + 2 >= now->indices.size())
            return false;
        const uint32_t* tri = now->indices.data() + std::size_t(prim) * 3;
        const uint32_t* was = before->indices.data() + std::size_t(prim) * 3;
        const std::size_t n = std::min(before->positions.size(), now->positions.size());
        if (tri[0] != was[0] || tri[1] != was[1] || tri[2] != was[2] || tri[0] >= n ||
            tri[1] >= n || tri[2] >= n)
            return false;
        const auto at = [&](const SurfaceVertices& s) {
            return (1.0f - b.x - b.y) * s.positions[tri[0]] + b.x * s.positions[tri[1]] +
                   b.y * s.positions[tri[2]];
        };
        moved =
            transform_point(before_to_world, at(*before)) - transform_point(now_to_world, at(*now));
        return true;
    }
};

// How this frame's surfaces moved since the last: the camera, and each instance that moved.
// Per pixel, reprojection asks about the instance it sees; below kTableIds ids the answers sit
// in arrays indexed by id (a set or map lookup per pixel cost a third of the blend), larger
// ids (a long game's) take the trees.
struct Motion {
    enum Flag : uint8_t { kMoving = 1, kInView = 2, kInPrevious = 4, kDeformed = 8 };
    static constexpr uint32_t kTableIds = 1u << 20;
    bool camera_moved = false;
    std::set<uint32_t> moving;                     // moved, deformed or new instances
    std::map<uint32_t, Mat4> to_previous;          // this frame's world to last frame's, per mover
    std::vector<uint8_t> flags;                    // by id
    std::vector<const Mat4*> motion;               // by id: into to_previous, or null
    std::map<uint32_t, Deformation> deformations;  // deformed instances with vertices known
    std::vector<const Deformation*> deformation;   // by id: into deformations, or null
    // Per pixel, 1 within a pixel of a moving instance in this frame's G-buffer and in the
    // last's (near_moving); null when nothing moved.
    const uint8_t* near_now = nullptr;
    const uint8_t* near_prev = nullptr;
    const FrameView* prev = nullptr;
    const FrameView* view = nullptr;

    uint8_t flags_of(uint32_t id) const {
        if (id < flags.size()) return flags[id];
        if (id < kTableIds) return 0;  // in no container: the table covers every id they hold
        return uint8_t((moving.count(id) ? kMoving : 0) |
                       (view->instances.count(id) ? kInView : 0) |
                       (prev->instances.count(id) ? kInPrevious : 0) |
                       (view->deformed.count(id) ? kDeformed : 0));
    }
    const Mat4* motion_of(uint32_t id) const {
        if (id < motion.size()) return motion[id];
        if (id < kTableIds) return nullptr;
        const auto it = to_previous.find(id);
        return it == to_previous.end() ? nullptr : &it->second;
    }
    const Deformation* deformation_of(uint32_t id) const {
        if (id < deformation.size()) return deformation[id];
        if (id < kTableIds) return nullptr;
        const auto it = deformations.find(id);
        return it == deformations.end() ? nullptr : &it->second;
    }
};

// The motion from `prev` to `view`; `before`: the surfaces' vertices as they were in `prev`.
Motion motion_between(const FrameView& prev, const FrameView& view, const SurfaceMap& before);

// Marks both frames' pixels near a moving instance (Motion::near_now, near_prev), in `now` and
// `before`; `tmp` is scratch.
void mark_near_moving(Motion& m, std::vector<uint8_t>& tmp, std::vector<uint8_t>& now,
                      std::vector<uint8_t>& before);

}  // namespace pathfarm::coord
