// The G-buffer the farm makes of a frame: from the first hits of a tracer's render (Embree).
#pragma once

#include "common/scene/scene_model.h"
#include "common/scene/scene_state.h"
#include "coordinator/converge/gbuffer.h"

namespace pathfarm::test {

// The G-buffer the farm makes of frame k of `scene` seen from `camera`: from the first hits of a
// tracer's render of that frame, from the scene graph's model as a replica holds it.
// `scale` < 1: workload scaling rendered that much smaller, the G-buffer is upscaled.
coord::GBuffer first_hit_gbuffer(const SceneModel& scene, const Camera& camera, uint32_t k,
                                 int display_w, int display_h, float scale = 1.0f);
// The same of the scene graph's state as it is now (a replica's model of it).
coord::GBuffer first_hit_gbuffer(const SceneState& state, const Camera& camera, uint32_t k,
                                 int display_w, int display_h, float scale = 1.0f);

}  // namespace pathfarm::test
