// SceneGraph: import, animation, change tracking and the application API.
#include "coordinator/scene_graph/scene_graph.h"

#include "coordinator/animation/animator.h"
#include "coordinator/animation/skinning.h"

namespace pathfarm::coord {
namespace {

void remap_ref(TextureRef& ref, const std::vector<uint32_t>& ids) {
    if (ref.texture >= 0 && ref.texture < int(ids.size()))
        ref.texture = int(ids[ref.texture]);
    else
        ref.texture = -1;
}

Mesh without_deformation_data(Mesh m) {
    m.joints.clear();
    m.weights.clear();
    m.morph_targets.clear();
    m.default_morph_weights.clear();
    return m;
}

// The smallest vertex range where a and b differ; empty when equal.
VertexRange changed_range(const Mesh& a, const Mesh& b) {
    VertexRange r;
    const std::size_t n = std::min(a.positions.size(), b.positions.size());
    const auto differs = [&](std::size_t v) {
        return a.positions[v] != b.positions[v] ||
               (a.has_normals() && a.normals[v] != b.normals[v]) ||
               (a.has_tangents() && a.tangents[v] != b.tangents[v]);
    };
    std::size_t first = 0;
    while (first < n && !differs(first))
        ++first;
    if (first == n) return r;
    std::size_t last = n;
    while (last > first && !differs(last - 1))
        --last;
    r.extend(uint32_t(first), uint32_t(last));
    return r;
}

}  // namespace

SceneGraph::SceneGraph(SceneModel scene) : source_(std::move(scene)) {
    import(source_);
    if (!source_.animations.empty()) clip_ = 0;
    advance(0.0);
    changes_ = ChangeSet{};  // the initial state reaches replicas as a snapshot
}

void SceneGraph::import(const SceneModel& scene) {
    std::vector<uint32_t> image_ids, texture_ids, material_ids, mesh_ids;
    for (const Image& img : scene.images)
        state_.images.emplace(image_ids.emplace_back(new_id()), img);
    for (Texture t : scene.textures) {
        t.image = t.image >= 0 ? int(image_ids[t.image]) : -1;
        state_.textures.emplace(texture_ids.emplace_back(new_id()), t);
    }
    for (Material m : scene.materials) {
        for (TextureRef* r : {&m.base_color_texture, &m.metallic_roughness_texture,
                              &m.normal_texture, &m.emissive_texture})
            remap_ref(*r, texture_ids);
        state_.materials.emplace(material_ids.emplace_back(new_id()), std::move(m));
    }
    for (const Mesh& src : scene.meshes) {
        Mesh m = without_deformation_data(src);
        m.material = int(material_ids[src.material]);
        state_.meshes.emplace(mesh_ids.emplace_back(new_id()), std::move(m));
    }
    nodes_.resize(scene.nodes.size());
    for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
        GraphNode& g = nodes_[n];
        for (int src_mesh : scene.nodes[n].meshes) {
            const Instance probe{src_mesh, int(n), Mat4(1.0f)};
            const bool deforming = is_deforming(scene, probe);
            uint32_t mesh_id = mesh_ids[src_mesh];
            if (deforming) {  // each deforming instance replicates its own deformed copy
                mesh_id = new_id();
                state_.meshes.emplace(mesh_id, state_.meshes.at(mesh_ids[src_mesh]));
            }
            const uint32_t inst = new_id();
            // A deforming instance is dynamic from the start (InstanceState::dynamic).
            state_.instances.emplace(inst, InstanceState{mesh_id, Mat4(1.0f), deforming});
            g.instance_ids.push_back(inst);
            g.mesh_ids.push_back(mesh_id);
            g.source_meshes.push_back(src_mesh);
            g.deforming.push_back(deforming);
            g.placed.push_back(false);
        }
        const int cam = scene.nodes[n].camera;
        if (cam >= 0 && cam < int(scene.cameras.size())) {
            g.camera_id = new_id();
            state_.cameras.emplace(*g.camera_id, scene.cameras[cam]);
            if (state_.cameras.size() == 1) state_.active_camera = *g.camera_id;
        }
    }
    state_.environment = scene.environment;
}

ChangeSet SceneGraph::take_changes() {
    ChangeSet out = std::move(changes_);
    changes_ = ChangeSet{};
    return out;
}

void SceneGraph::advance(double clock_seconds) {
    dynamic_triangles_ = 0;
    if (clip_ && *clip_ >= 0 && *clip_ < int(source_.animations.size())) {
        apply_clip(source_, *clip_, looped_clip_time(source_.animations[*clip_], clock_seconds));
        transforms_dirty_ = true;
    }
    refresh();
}

void SceneGraph::refresh() {
    if (!transforms_dirty_) return;
    const std::vector<Mat4> world = node_world_transforms(source_);
    update_world_transforms(world);
    update_deformed(world);
    transforms_dirty_ = false;
}

void SceneGraph::update_world_transforms(const std::vector<Mat4>& world) {
    for (std::size_t n = 0; n < nodes_.size(); ++n) {
        GraphNode& g = nodes_[n];
        if (!g.alive) continue;
        for (std::size_t k = 0; k < g.instance_ids.size(); ++k) {
            // Skinned vertices are produced in world space (glTF ignores the node's transform).
            const bool skinned = g.deforming[k] && source_.nodes[n].skin >= 0;
            const Mat4 t = skinned ? Mat4(1.0f) : world[n];
            InstanceState& inst = state_.instances.at(g.instance_ids[k]);
            if (inst.transform != t) {
                inst.transform = t;
                // Moved after it was first placed: dynamic from now on (never back, so a
                // replica's layout follows the state alone, not the frames it saw).
                inst.dynamic = inst.dynamic || g.placed[k];
                changes_.instances_set.insert(g.instance_ids[k]);
            }
            g.placed[k] = true;
        }
        if (g.camera_id) {
            Mat4 m = world[n];
            for (int c = 0; c < 3; ++c)
                m[c] = Vec4(glm::normalize(Vec3(m[c])), 0.0f);
            Camera& cam = state_.cameras.at(*g.camera_id);
            if (cam.camera_to_world != m) {
                cam.camera_to_world = m;
                changes_.cameras_set.insert(*g.camera_id);
            }
        }
    }
}

void SceneGraph::update_deformed(const std::vector<Mat4>& world) {
    for (std::size_t n = 0; n < nodes_.size(); ++n) {
        const GraphNode& g = nodes_[n];
        if (!g.alive) continue;
        for (std::size_t k = 0; k < g.instance_ids.size(); ++k) {
            if (!g.deforming[k]) continue;
            const Mesh deformed =
                deform_instance(source_, Instance{g.source_meshes[k], int(n), world[n]}, world);
            Mesh& current = state_.meshes.at(g.mesh_ids[k]);
            const VertexRange r = changed_range(current, deformed);
            if (r.first == r.end) continue;
            std::copy(deformed.positions.begin() + r.first, deformed.positions.begin() + r.end,
                      current.positions.begin() + r.first);
            if (current.has_normals())
                std::copy(deformed.normals.begin() + r.first, deformed.normals.begin() + r.end,
                          current.normals.begin() + r.first);
            if (current.has_tangents())
                std::copy(deformed.tangents.begin() + r.first, deformed.tangents.begin() + r.end,
                          current.tangents.begin() + r.first);
            changes_.vertices_changed[g.mesh_ids[k]].extend(r.first, r.end);
            dynamic_triangles_ += current.triangle_count();
        }
    }
}

uint32_t SceneGraph::add_image(Image image) {
    const uint32_t id = new_id();
    state_.images.emplace(id, std::move(image));
    changes_.images_added.insert(id);
    return id;
}

uint32_t SceneGraph::add_texture(Texture texture) {
    const uint32_t id = new_id();
    state_.textures.emplace(id, texture);
    changes_.textures_set.insert(id);
    return id;
}

uint32_t SceneGraph::add_material(Material material) {
    const uint32_t id = new_id();
    state_.materials.emplace(id, std::move(material));
    changes_.materials_set.insert(id);
    return id;
}

Status SceneGraph::set_material(uint32_t id, Material material) {
    const auto it = state_.materials.find(id);
    if (it == state_.materials.end())
        return make_error(ErrorCode::not_found, "material {}: no such material", id);
    it->second = std::move(material);
    changes_.materials_set.insert(id);
    return {};
}

std::vector<uint32_t> SceneGraph::find_nodes(const std::string& name) const {
    std::vector<uint32_t> out;
    for (uint32_t n = 0; n < nodes_.size(); ++n)
        if (nodes_[n].alive && source_.nodes[n].name == name) out.push_back(n);
    return out;
}

std::optional<uint32_t> SceneGraph::node_of_instance(uint32_t instance) const {
    for (uint32_t n = 0; n < nodes_.size(); ++n)
        for (uint32_t id : nodes_[n].instance_ids)
            if (id == instance && nodes_[n].alive) return n;
    return std::nullopt;
}

std::optional<uint32_t> SceneGraph::find_material(const std::string& name) const {
    for (const auto& [id, m] : state_.materials)
        if (m.name == name) return id;
    return std::nullopt;
}

Status SceneGraph::set_light(uint32_t material, const Rgb& colour, float strength, bool on) {
    const auto it = state_.materials.find(material);
    if (it == state_.materials.end())
        return make_error(ErrorCode::not_found, "light {}: no such material", material);
    Material m = it->second;
    m.emissive_factor = on ? colour : Rgb(0.0f);
    m.emissive_strength = strength;
    return set_material(material, std::move(m));
}

uint32_t SceneGraph::add_mesh(Mesh mesh) {
    const uint32_t id = new_id();
    state_.meshes.emplace(id, without_deformation_data(std::move(mesh)));
    changes_.meshes_added.insert(id);
    return id;
}

Status SceneGraph::edit_vertices(uint32_t mesh, uint32_t first,
                                 const std::vector<Vec3>& positions) {
    const auto it = state_.meshes.find(mesh);
    if (it == state_.meshes.end())
        return make_error(ErrorCode::not_found, "mesh {}: no such mesh", mesh);
    if (std::size_t(first) + positions.size() > it->second.positions.size())
        return make_error(ErrorCode::invalid_argument, "mesh {}: vertices [{}, {}) beyond its {}",
                          mesh, first, first + positions.size(), it->second.positions.size());
    std::copy(positions.begin(), positions.end(), it->second.positions.begin() + first);
    if (!changes_.meshes_added.count(mesh))
        changes_.vertices_changed[mesh].extend(first, first + uint32_t(positions.size()));
    return {};
}

Result<uint32_t> SceneGraph::add_node(uint32_t mesh, const Mat4& transform,
                                      std::optional<uint32_t> parent) {
    if (!state_.meshes.count(mesh))
        return make_error(ErrorCode::not_found, "mesh {}: no such mesh", mesh);
    if (parent && !node_alive(*parent))
        return make_error(ErrorCode::not_found, "node {}: no such node", *parent);
    Node node;
    node.parent = parent ? int(*parent) : -1;
    node.local = transform;
    source_.nodes.push_back(std::move(node));
    GraphNode g;
    const uint32_t inst = new_id();
    state_.instances.emplace(inst, InstanceState{mesh, Mat4(1.0f)});
    g.instance_ids.push_back(inst);
    g.mesh_ids.push_back(mesh);
    g.source_meshes.push_back(-1);
    g.deforming.push_back(false);
    g.placed.push_back(false);
    nodes_.push_back(std::move(g));
    changes_.instances_set.insert(inst);
    transforms_dirty_ = true;
    refresh();
    return uint32_t(nodes_.size() - 1);
}

Status SceneGraph::set_node_transform(uint32_t node, const Mat4& local) {
    if (!node_alive(node)) return make_error(ErrorCode::not_found, "node {}: no such node", node);
    Node& n = source_.nodes[node];
    n.local = local;
    n.has_trs = false;  // an application matrix wins over animation of this node
    transforms_dirty_ = true;
    refresh();
    return {};
}

void SceneGraph::remove_instance(uint32_t node, std::size_t slot) {
    GraphNode& g = nodes_[node];
    state_.instances.erase(g.instance_ids[slot]);
    changes_.instances_set.erase(g.instance_ids[slot]);
    changes_.instances_removed.insert(g.instance_ids[slot]);
    if (g.deforming[slot]) {
        state_.meshes.erase(g.mesh_ids[slot]);
        changes_.vertices_changed.erase(g.mesh_ids[slot]);
        changes_.meshes_removed.insert(g.mesh_ids[slot]);
    }
    for (auto* v : {&g.instance_ids, &g.mesh_ids})
        v->erase(v->begin() + std::ptrdiff_t(slot));
    g.source_meshes.erase(g.source_meshes.begin() + std::ptrdiff_t(slot));
    g.deforming.erase(g.deforming.begin() + std::ptrdiff_t(slot));
    g.placed.erase(g.placed.begin() + std::ptrdiff_t(slot));
}

Status SceneGraph::remove_node(uint32_t node) {
    if (!node_alive(node)) return make_error(ErrorCode::not_found, "node {}: no such node", node);
    // Children follow their parents in the node list, so one forward pass finds the subtree.
    std::vector<bool> doomed(nodes_.size(), false);
    doomed[node] = true;
    for (std::size_t n = node + 1; n < nodes_.size(); ++n)
        doomed[n] = source_.nodes[n].parent >= 0 && doomed[source_.nodes[n].parent];
    for (std::size_t n = node; n < nodes_.size(); ++n) {
        if (!doomed[n] || !nodes_[n].alive) continue;
        while (!nodes_[n].instance_ids.empty())
            remove_instance(uint32_t(n), 0);
        nodes_[n].alive = false;
    }
    return {};
}

Status SceneGraph::remove_mesh(uint32_t mesh) {
    if (!state_.meshes.count(mesh))
        return make_error(ErrorCode::not_found, "mesh {}: no such mesh", mesh);
    for (std::size_t n = 0; n < nodes_.size(); ++n)
        for (std::size_t k = nodes_[n].mesh_ids.size(); k-- > 0;)
            if (nodes_[n].mesh_ids[k] == mesh) remove_instance(uint32_t(n), k);
    state_.meshes.erase(mesh);
    changes_.vertices_changed.erase(mesh);
    if (!changes_.meshes_added.erase(mesh)) changes_.meshes_removed.insert(mesh);
    return {};
}

uint32_t SceneGraph::set_camera(std::optional<uint32_t> id, const Camera& camera, bool active) {
    const uint32_t cam = id ? *id : new_id();
    // The application's pose wins over the node the camera hangs from (as set_node_transform
    // wins over animation): the node no longer moves this camera.
    for (GraphNode& g : nodes_)
        if (g.camera_id == cam) g.camera_id.reset();
    state_.cameras[cam] = camera;
    changes_.cameras_set.insert(cam);
    if (active && state_.active_camera != cam) {
        state_.active_camera = cam;
        changes_.active_camera = true;
    }
    return cam;
}

void SceneGraph::set_environment(const Environment& environment) {
    state_.environment = environment;
    changes_.environment = true;
}

void SceneGraph::set_settings(const RenderSettings& settings) {
    state_.settings = settings;
    changes_.settings = true;
}

}  // namespace pathfarm::coord
