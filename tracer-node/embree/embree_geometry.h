// One Embree triangle geometry as the tracer's scene keeps it: its vertex buffer written from a
// mesh, and the alpha filter that follows the mesh's material. Only the Embree scene's own
// sources include this (it pulls in Embree's header).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include <embree3/rtcore.h>

#include "common/scene/scene_model.h"

namespace pathfarm::tracer {

const char* embree_error_name(RTCError code);

// What an alpha-tested geometry's filter needs (glTF MASK / BLEND: common/scene/alpha.h). The
// scene pointer follows every update; the mesh is found by index in it.
struct AlphaGeometry {
    const SceneModel* scene = nullptr;
    uint32_t mesh = 0;
};

// One Embree triangle geometry and what its alpha filter reads.
struct TriangleGeometry {
    RTCGeometry geom = nullptr;  // owned by its scene
    std::size_t vertex_count = 0;
    bool filtered = false;  // alpha filter installed
    std::unique_ptr<AlphaGeometry> alpha = std::make_unique<AlphaGeometry>();
};

// Writes the mesh's positions into the geometry's vertex buffer (allocated when its size
// changed), moved by `to_model` when given: exactly the arithmetic ShadingScene uses, so hits
// and shading agree.
void write_positions(TriangleGeometry& g, const Mesh& mesh, const Mat4* to_model);

// Installs or removes the alpha filter to follow the mesh's material; true if it changed.
bool follow_material(TriangleGeometry& g, const SceneModel& scene);

}  // namespace pathfarm::tracer
