// SceneChanges helpers.
#include "tracer-node/backend/render_backend.h"

namespace pathfarm::tracer {

SceneChanges SceneChanges::everything() {
    SceneChanges c;
    c.structure = c.lights = c.camera = c.settings = c.environment = true;
    return c;
}

bool SceneChanges::empty() const {
    return !structure && instances.empty() && mesh_vertices.empty() && materials.empty() &&
           textures.empty() && !lights && !camera && !settings && !environment;
}

}  // namespace pathfarm::tracer
