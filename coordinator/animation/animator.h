// Applying animation clips to a scene's nodes.
#pragma once

#include <string>

#include "common/base/result.h"
#include "common/scene/scene_model.h"

namespace pathfarm::coord {

// Finds a clip by name or by decimal index.
Result<int> find_clip(const SceneModel& scene, const std::string& name_or_index);

// Sets the TRS and morph weights of every node the clip targets to their values at time t of
// the clip's own timeline, then rebuilds the nodes' local matrices and the instances.
void apply_clip(SceneModel& scene, int clip, float t);

// Time inside a looping clip for a game clock time (seconds since the clip started playing).
float looped_clip_time(const AnimationClip& clip, double clock_seconds);

}  // namespace pathfarm::coord
