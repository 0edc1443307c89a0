// Seeded random lighting configurations for estimator-agreement tests: one emitter of random
// shape, size, distance, orientation, sidedness, node transform and emission texture over a
// receiver of one of every material kind, or the sun/sky alone. Tests that search instead of
// confirm: a property of the integrator must hold for all of them (the tilted-light bias
// passed every hand-made scene).
#pragma once

#include <cstdint>
#include <string>

#include "common/scene/scene_model.h"

namespace pathfarm::test {

enum class EmitterShape : uint8_t { triangle, quad, closed_mesh, sky };
enum class EmitterTransform : uint8_t { rotated, scaled, non_uniform, mirrored, parented };
enum class ReceiverKind : uint8_t {
    lambert,
    textured_lambert,
    rough_plastic,
    normal_mapped_plastic,
    rough_metal,
    mirror,
    rough_glass,
    smooth_glass,
};
inline constexpr int kReceiverKinds = 8;

struct LightingCase {
    uint32_t index = 0;
    EmitterShape shape = EmitterShape::quad;
    EmitterTransform transform = EmitterTransform::rotated;
    ReceiverKind receiver = ReceiverKind::lambert;
    float size_m = 1.0f;      // the emitter's extent (edge or diameter) in world space
    float distance_m = 1.0f;  // from the receiver's centre to the emitter's centre
    bool double_sided = false;
    bool textured_emission = false;
    // Whether BSDF-only sampling finds the light often enough for a block test at the suite's
    // budget: not for the 0.5-degree sun, nor for emitters under ~0.01 sr (size/distance < 0.1),
    // where it hits the light less than once per block and batch, so its batch means are far
    // from normal. Light-only and MIS are compared in every case.
    bool bsdf_informative = true;
    SceneModel scene;
    // One line naming every random choice, for failure messages.
    std::string describe() const;
};

// Case `index` of the suite: every shape, transform and receiver kind recurs with a period
// (so any 24 consecutive cases contain each of them); sizes, distances, orientations, sides and
// textures are drawn from a generator seeded by the index. Radiance is scaled by
// distance² / size² so that every case lights its receiver about equally.
LightingCase make_lighting_case(uint32_t index);

}  // namespace pathfarm::test
