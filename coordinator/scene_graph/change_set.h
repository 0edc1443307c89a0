// ChangeSet: what changed in the replicated SceneState since the last commit (the dirty flags
// of Cycles' ObjectManager, per object id). The commit builder turns it into ops.
#pragma once

#include <cstdint>
#include <map>
#include <set>

namespace pathfarm::coord {

struct VertexRange {
    uint32_t first = 0;
    uint32_t end = 0;  // one past the last changed vertex
    void extend(uint32_t begin_vertex, uint32_t end_vertex) {
        if (first == end) {
            first = begin_vertex;
            end = end_vertex;
        } else {
            first = std::min(first, begin_vertex);
            end = std::max(end, end_vertex);
        }
    }
};

struct ChangeSet {
    std::set<uint32_t> images_added, images_removed;
    std::set<uint32_t> textures_set, textures_removed;
    std::set<uint32_t> materials_set, materials_removed;
    std::set<uint32_t> meshes_added, meshes_removed;
    std::map<uint32_t, VertexRange> vertices_changed;  // mesh id -> changed vertex range
    std::set<uint32_t> instances_set, instances_removed;
    std::set<uint32_t> cameras_set;
    bool active_camera = false;
    bool environment = false;
    bool settings = false;

    bool empty() const {
        return images_added.empty() && images_removed.empty() && textures_set.empty() &&
               textures_removed.empty() && materials_set.empty() && materials_removed.empty() &&
               meshes_added.empty() && meshes_removed.empty() && vertices_changed.empty() &&
               instances_set.empty() && instances_removed.empty() && cameras_set.empty() &&
               !active_camera && !environment && !settings;
    }
};

}  // namespace pathfarm::coord
