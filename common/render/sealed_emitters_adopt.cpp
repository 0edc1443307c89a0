// What SealedEmitters keeps from one scene state to the next: the whole analysis when the scene
// only moved as a whole (camera-relative rendering), and the closed surfaces of whatever did not
// move when some instances moved on their own (a rolling ball, a swinging door, a ring of
// lights). Either way the result is the one a new analysis of the new state would give.
#include <algorithm>
#include <bit>
#include <cstring>
#include <numeric>
#include <optional>
#include <tuple>

#include "common/base/hash.h"
#include "common/math/transform.h"
#include "common/render/sealed_emitters.h"

namespace pathfarm {

uint64_t SealedEmitters::layout_hash(const SceneModel& scene) {
    uint64_t h = fnv1a64(nullptr, 0);
    auto add = [&h](const void* data, std::size_t size) { h = hash_bytes_fast(data, size, h); };
    for (const Mesh& m : scene.meshes) {
        add(m.indices.data(), m.indices.size() * sizeof(uint32_t));
        const uint64_t vertices = m.positions.size();
        add(&vertices, sizeof vertices);
        add(&m.material, sizeof m.material);
    }
    for (const Material& m : scene.materials) {
        const uint8_t flags = uint8_t(occludes(m)) | uint8_t(m.is_emissive() << 1);
        add(&flags, 1);
    }
    for (const Instance& inst : scene.instances)
        add(&inst.mesh, sizeof inst.mesh);
    return h;
}

std::vector<uint64_t> SealedEmitters::position_hashes(const SceneModel& scene) {
    std::vector<uint64_t> out;
    out.reserve(scene.meshes.size());
    for (const Mesh& m : scene.meshes)
        out.push_back(hash_bytes_fast(m.positions.data(), m.positions.size() * sizeof(Vec3)));
    return out;
}

bool SealedEmitters::same_layout(const SceneModel& scene) const {
    return scene.instances.size() == instance_count_ && layout_hash(scene) == layout_hash_;
}

bool SealedEmitters::adopt_translated(const SceneModel& scene) {
    return same_layout(scene) && position_hashes(scene) == position_hashes_ && translated(scene);
}

bool SealedEmitters::translated(const SceneModel& scene) {
    std::optional<glm::dvec3> delta;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const Mat4& m = scene.instances[i].transform;
        if (Mat3(m) != linear_[i]) return false;
        const glm::dvec3 d = glm::dvec3(Vec3(m[3])) - translation_[i];
        if (!delta) delta = d;
        // Camera-relative shifts are computed in double and rounded to float per instance.
        const double tolerance = 1e-6 * (1.0 + glm::length(glm::dvec3(Vec3(m[3]))));
        if (glm::length(d - *delta) > tolerance) return false;
    }
    shift_ = delta.value_or(glm::dvec3(0.0));
    return true;
}

bool SealedEmitters::placed_as_analysed(const SceneModel& scene, std::size_t i) const {
    const Mat4& m = scene.instances[i].transform;
    return Mat3(m) == linear_[i] && glm::dvec3(Vec3(m[3])) == translation_[i];
}

bool SealedEmitters::adopt(const SceneModel& scene) {
    if (!same_layout(scene)) return false;
    std::vector<uint64_t> positions = position_hashes(scene);
    if (positions == position_hashes_) return translated(scene) || moved_instances(scene, {});
    std::vector<bool> deformed(positions.size());
    for (std::size_t m = 0; m < positions.size(); ++m)
        deformed[m] = positions[m] != position_hashes_[m];
    // Where the deformed occluders hold most of the occluder triangles (a skinned figure
    // alone), little is kept and welding them again alone costs more than a new analysis.
    std::size_t occluding = 0, reshaped = 0;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        if (!occludes(material_of(scene, i))) continue;
        const std::size_t mesh = std::size_t(scene.instances[i].mesh);
        occluding += scene.meshes[mesh].triangle_count();
        reshaped += deformed[mesh] ? scene.meshes[mesh].triangle_count() : 0;
    }
    if (2 * reshaped > occluding || !moved_instances(scene, deformed)) return false;
    position_hashes_ = std::move(positions);
    return true;
}

bool SealedEmitters::adopt_moved_instances(const SceneModel& scene) {
    return same_layout(scene) && position_hashes(scene) == position_hashes_ &&
           moved_instances(scene, {});
}

bool SealedEmitters::moved_instances(const SceneModel& scene, const std::vector<bool>& deformed) {
    if (shift_ != glm::dvec3(0.0)) return false;
    if (skipped_) return true;  // the same occluders: over the limit still
    const auto reshaped = [&](uint32_t i) {
        return !deformed.empty() && deformed[std::size_t(scene.instances[i].mesh)];
    };
    std::vector<uint32_t> moved, occluders, emitters;
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        if (!reshaped(i) && placed_as_analysed(scene, i)) continue;
        moved.push_back(i);
        const Material& m = material_of(scene, i);
        if (occludes(m)) {
            // Its closed surfaces may be joined with another instance's.
            if (!isolated_[i]) return false;
            occluders.push_back(i);
        }
        if (m.is_emissive()) emitters.push_back(i);
    }
    for (uint32_t i : occluders)
        remove_occluder(scene, i, reshaped(i));
    std::erase_if(enclosures_, [&](const Enclosure& e) {
        return std::binary_search(occluders.begin(), occluders.end(), e.owner);
    });
    // The others' sides of the moved emitters, before the moved occluders' new enclosures
    // (which find every emitter's side where it is now) are added.
    for (Enclosure& e : enclosures_)
        for (auto& [instance, side] : e.emitters)
            if (std::binary_search(emitters.begin(), emitters.end(), instance))
                side = emitter_side(e, scene.instances[instance],
                                    scene.meshes[std::size_t(scene.instances[instance].mesh)]);
    for (uint32_t i : occluders)
        if (!moved_occluder(scene, i)) return false;
    for (uint32_t i : moved) {
        linear_[i] = Mat3(scene.instances[i].transform);
        translation_[i] = glm::dvec3(Vec3(scene.instances[i].transform[3]));
    }
    return true;
}

void SealedEmitters::remove_occluder(const SceneModel& scene, uint32_t i, bool deformed) {
    if (deformed) {
        // Its old vertices are not in the scene any more: those it owns leave (an isolated
        // occluder owns all of its own), and its surfaces are welded again where it is now.
        std::erase_if(vertex_owner_, [i](const auto& entry) { return entry.second == i; });
        mesh_surfaces_.erase(i);
        return;
    }
    MeshSurfaces& surfaces = surfaces_of(scene, i);
    if (!surfaces.placed) {  // where the analysis found it
        Mat4 analysed(linear_[i]);
        analysed[3] = Vec4(Vec3(translation_[i]), 1.0f);
        std::vector<uint32_t> merged;
        surfaces.keys = place(surfaces, analysed, merged);
    }
    for (const WeldKey& key : surfaces.keys)
        if (auto it = vertex_owner_.find(key); it != vertex_owner_.end() && it->second == i)
            vertex_owner_.erase(it);
}

SealedEmitters::MeshSurfaces& SealedEmitters::surfaces_of(const SceneModel& scene, uint32_t i) {
    MeshSurfaces& surfaces = mesh_surfaces_[i];
    if (surfaces.welding.corner_ids.empty()) {
        const Mesh& mesh = scene.meshes[std::size_t(scene.instances[i].mesh)];
        std::vector<Vec3> tris;
        tris.reserve(mesh.indices.size());
        for (uint32_t v : mesh.indices)
            tris.push_back(mesh.positions[v]);
        surfaces.welding = weld(tris);
    }
    return surfaces;
}

std::vector<WeldKey> SealedEmitters::place(const MeshSurfaces& surfaces, const Mat4& transform,
                                           std::vector<uint32_t>& merged) {
    // Each own vertex where it is placed (a key's bits are its position, but for the sign of
    // a zero, which cannot move it to another world key), and which of them meet.
    const std::vector<WeldKey>& object_keys = surfaces.welding.keys;
    std::vector<WeldKey> world(object_keys.size());
    for (std::size_t id = 0; id < object_keys.size(); ++id) {
        const WeldKey& k = object_keys[id];
        world[id] = weld_key(transform_point(
            transform,
            Vec3(std::bit_cast<float>(k.x), std::bit_cast<float>(k.y), std::bit_cast<float>(k.z))));
    }
    std::vector<uint32_t> order(world.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        return std::tie(world[a].x, world[a].y, world[a].z, a) <
               std::tie(world[b].x, world[b].y, world[b].z, b);
    });
    merged.resize(world.size());
    std::vector<WeldKey> keys;
    for (std::size_t r = 0; r < order.size(); ++r) {
        const bool met = r > 0 && world[order[r]] == world[order[r - 1]];
        merged[order[r]] = met ? merged[order[r - 1]] : order[r];
        if (!met) keys.push_back(world[order[r]]);
    }
    return keys;
}

bool SealedEmitters::moved_occluder(const SceneModel& scene, uint32_t i) {
    const Instance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[std::size_t(inst.mesh)];
    MeshSurfaces& surfaces = surfaces_of(scene, i);
    std::vector<uint32_t> merged;
    surfaces.keys = place(surfaces, inst.transform, merged);
    surfaces.placed = true;
    for (const WeldKey& key : surfaces.keys)
        // A vertex another occluder has too: the surfaces may join, which only a new
        // analysis sees.
        if (!vertex_owner_.emplace(key, i).second) return false;
    if (surfaces.fresh || merged != surfaces.merged) {
        Welding placed;
        placed.corner_ids.reserve(surfaces.welding.corner_ids.size());
        for (uint32_t id : surfaces.welding.corner_ids)
            placed.corner_ids.push_back(merged[id]);
        surfaces.closed = closed_components(placed);
        surfaces.merged = std::move(merged);
        surfaces.fresh = false;
    }
    if (surfaces.closed.empty()) return true;
    std::vector<Vec3> tris;  // as a new analysis places them, corner by corner
    tris.reserve(mesh.indices.size());
    for (uint32_t v : mesh.indices)
        tris.push_back(transform_point(inst.transform, mesh.positions[v]));
    add_enclosures(scene, tris, std::vector<uint32_t>(tris.size() / 3, i), surfaces.closed);
    return true;
}

}  // namespace pathfarm
