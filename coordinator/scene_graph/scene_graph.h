// SceneGraph: the coordinator's scene (DESIGN.md, "The frame" step 1). It owns the node
// hierarchy, animation clips and skins, and the replicated SceneState derived from them, and
// records every change in a ChangeSet. All objects have stable ids; ids are never reused.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/scene/scene_state.h"
#include "coordinator/scene_graph/change_set.h"

namespace pathfarm::coord {

class SceneGraph {
public:
    // Takes the loaded scene: nodes, meshes, materials, textures, cameras, skins, clips.
    explicit SceneGraph(SceneModel scene);

    const SceneState& state() const { return state_; }
    const ChangeSet& changes() const { return changes_; }
    ChangeSet take_changes();

    // --- Frame: animation on the fixed game clock (DESIGN.md, "Time").
    // Plays `clip` (looping) at clock time t and brings instance transforms and deformed
    // meshes up to date. No clip (or none in the scene): only pending node edits apply.
    void advance(double clock_seconds);
    void set_playing_clip(std::optional<int> clip) { clip_ = clip; }
    // Triangles whose vertices changed in the last advance().
    std::size_t dynamic_triangles() const { return dynamic_triangles_; }

    // --- Application API.
    uint32_t add_image(Image image);
    uint32_t add_texture(Texture texture);  // texture.image is an image id
    uint32_t add_material(Material material);
    Status set_material(uint32_t id, Material material);
    // Lights are emissive materials: colour and strength edit the emission; off sets it to 0.
    Status set_light(uint32_t material, const Rgb& colour, float strength, bool on);
    uint32_t add_mesh(Mesh mesh);  // mesh.material is a material id
    Status edit_vertices(uint32_t mesh, uint32_t first, const std::vector<Vec3>& positions);
    // A new root node with one instance of `mesh`; returns the node id.
    Result<uint32_t> add_node(uint32_t mesh, const Mat4& transform,
                              std::optional<uint32_t> parent = {});
    Status set_node_transform(uint32_t node, const Mat4& local);
    Status remove_node(uint32_t node);  // and its subtree's instances
    Status remove_mesh(uint32_t mesh);  // instances of it are removed too
    // A camera that hung from a node is detached from it: the application now poses it.
    uint32_t set_camera(std::optional<uint32_t> id, const Camera& camera, bool active);
    void set_environment(const Environment& environment);
    void set_settings(const RenderSettings& settings);

    // Lookups for game logic: alive nodes with this name, and the node showing an instance.
    std::vector<uint32_t> find_nodes(const std::string& name) const;
    std::optional<uint32_t> node_of_instance(uint32_t instance) const;
    std::optional<uint32_t> find_material(const std::string& name) const;

    std::size_t node_count() const { return nodes_.size(); }
    bool node_alive(uint32_t node) const { return node < nodes_.size() && nodes_[node].alive; }

private:
    // Bookkeeping per node; the node's hierarchy and TRS live in source_.nodes (same index).
    struct GraphNode {
        bool alive = true;
        std::vector<uint32_t> instance_ids;
        std::vector<uint32_t> mesh_ids;  // per instance: the replicated mesh it shows
        std::vector<int> source_meshes;  // per instance: index in source_.meshes, or -1
        std::vector<bool> deforming;     // per instance: skinned or morphed
        std::vector<bool> placed;        // per instance: its first transform has been set
        std::optional<uint32_t> camera_id;
    };

    void import(const SceneModel& scene);
    void refresh();  // brings instances, cameras and deformed meshes up to date with the nodes
    void update_world_transforms(const std::vector<Mat4>& world);
    void update_deformed(const std::vector<Mat4>& world);
    void remove_instance(uint32_t node, std::size_t slot);
    uint32_t new_id() { return next_id_++; }

    SceneModel source_;  // nodes, skins, clips and the undeformed meshes (by source index)
    std::vector<GraphNode> nodes_;
    SceneState state_;
    ChangeSet changes_;
    std::optional<int> clip_;
    std::size_t dynamic_triangles_ = 0;
    uint32_t next_id_ = 1;
    bool transforms_dirty_ = true;
};

}  // namespace pathfarm::coord
