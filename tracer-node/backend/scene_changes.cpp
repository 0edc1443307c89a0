// SceneChanges helpers.
#include "tracer-node/backend/render_backend.h"

namespace pathfarm::tracer {

SceneChanges SceneChanges::everything() {
    SceneChanges c;
    c.structure = c.lights = c.camera = c.settings = c.environment = true;
    return c;
}

SceneChanges diff_scenes(const SceneModel& before, const SceneModel& after) {
    SceneChanges c;
    if (before.instances.size() != after.instances.size() ||
        before.meshes.size() != after.meshes.size())
        return SceneChanges::everything();
    for (uint32_t i = 0; i < after.instances.size(); ++i) {
        // Becoming dynamic changes the backend's layout (Instance::dynamic).
        if (before.instances[i].dynamic != after.instances[i].dynamic)
            return SceneChanges::everything();
        if (before.instances[i].transform != after.instances[i].transform) c.instances.push_back(i);
    }
    for (uint32_t m = 0; m < after.meshes.size(); ++m)
        if (before.meshes[m].positions != after.meshes[m].positions) c.mesh_vertices.push_back(m);
    const auto eye = [](const SceneModel& s) {
        return s.cameras.empty() ? Mat4(1.0f) : s.cameras[0].camera_to_world;
    };
    c.camera = eye(before) != eye(after);
    return c;
}

void recentre_for_backend(SceneModel& scene, const glm::dvec3& previous_origin,
                          SceneChanges& changes) {
    recentre_on_camera(scene, scene.cameras.empty() ? Camera{} : scene.cameras[0]);
    if (changes.structure || scene.origin == previous_origin) return;
    changes.instances.resize(scene.instances.size());
    for (uint32_t i = 0; i < changes.instances.size(); ++i)
        changes.instances[i] = i;
}

SceneChanges SceneStepper::step(SceneModel world) {
    SceneChanges changes = started_ ? diff_scenes(previous_, world) : SceneChanges::everything();
    started_ = true;
    previous_ = world;
    const glm::dvec3 origin = current_.origin;
    current_ = std::move(world);
    recentre_for_backend(current_, origin, changes);
    return changes;
}

bool SceneChanges::empty() const { return view_only() && !camera && !settings; }

}  // namespace pathfarm::tracer
