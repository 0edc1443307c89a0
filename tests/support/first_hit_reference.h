// First hits found again by brute force, in double precision over every triangle of a scene
// (tests/render/first_hits*_test.cpp): the closest hit of a ray, and what the denoiser is
// shown through mirrors and clear glass (PathTracer::first_hit's primary surface replacement).
#pragma once

#include <cstdint>

#include "common/film/first_hits.h"
#include "common/math/types.h"
#include "common/scene/scene_model.h"

namespace pathfarm::test {

struct ReferenceHit {
    double t = INFINITY;
    uint32_t instance = FirstHit::kNone;
    uint32_t prim = 0;
    double u = 0.0, v = 0.0;
};

// Closest hit of `ray` beyond 1e-4 over every triangle of every instance (Moller-Trumbore).
ReferenceHit brute_force(const SceneModel& scene, const Ray& ray);

const Material& material_of(const SceneModel& scene, uint32_t instance);

// A mirror-like metal or clear glass (not emitting), which a first hit sees through.
bool passes_light_on(const Material& m);

// What the denoiser is shown through a mirror-like metal or clear glass: the first other
// surface, the length of the path to it, and whether the path got there (an emitter or the sky
// on the way, or more than kMaxReplacedBounces of them, leave the first hit as it was).
struct Beyond {
    bool replaced = false;
    double travelled = 0.0;
    uint32_t instance = FirstHit::kNone;
    glm::dvec3 normal{0.0};  // as the mirrors passed show it, facing the camera
};

// The chain from `ray`'s closest hit `hit` (brute_force's), reflecting and refracting by the
// meshes' interpolated shading normals.
Beyond follow_through(const SceneModel& scene, Ray ray, ReferenceHit hit);

}  // namespace pathfarm::test
