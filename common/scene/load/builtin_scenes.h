// Scenes compiled into pathfarm, addressed as builtin:NAME.
#pragma once

#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/scene/scene_model.h"

namespace pathfarm {

// The classic Cornell box (Lambert walls, one quad light), in metres.
SceneModel make_cornell_box();
// The demo room: instanced objects, procedural floor, mirror, absorbing glass, several lights
// of different sizes and a sunlit window.
SceneModel make_default_scene();
// Benchmark scenes: specular chains (glass, absorbing glass, mirror, polished metal), and a room
// lit by 1024 small emissive quads (bench/time_vs_error.py).
SceneModel make_glass_scene();
SceneModel make_many_lights_scene();
SceneModel make_light_field_scene();
SceneModel make_sealed_lights_scene();
SceneModel make_furnace_scene();
// The default scene's door node transform, swung open by `open_radians` about its hinge.
Mat4 default_scene_door_transform(float open_radians);

std::vector<std::string> builtin_scene_names();
Result<SceneModel> make_builtin_scene(const std::string& name);

}  // namespace pathfarm
