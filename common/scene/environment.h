// What lights a scene besides its emissive triangles: the analytic sun and sky.
#pragma once

#include "common/math/types.h"

namespace pathfarm {

// DESIGN.md: a scene with emitters is lit by them alone; one without is lit by the sun/sky.
// `automatic` implements exactly that; built-in scenes may force the sun/sky on (a window
// letting the sun into a lit room) or off (analytic test enclosures).
enum class SkyMode : uint8_t { automatic, on, off };
inline constexpr int kSkyModeCount = 3;

struct Environment {
    SkyMode sky = SkyMode::automatic;
    Vec3 sun_direction = glm::normalize(Vec3(0.35f, 0.8f, 0.45f));  // towards the sun, world space
    float turbidity = 3.0f;
    float sun_scale = 1.0f;  // multiplies both sun and sky radiance
};

}  // namespace pathfarm
