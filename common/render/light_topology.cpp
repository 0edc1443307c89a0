// Per-mesh light trees in mesh space, and their cache (light_topology.h).
#include "common/render/light_topology.h"

#include <vector>

#include "common/base/hash.h"

namespace pathfarm {
namespace {

uint64_t geometry_key(const Mesh& mesh, bool two_sided) {
    uint64_t h = fnv1a64(reinterpret_cast<const unsigned char*>(mesh.positions.data()),
                         mesh.positions.size() * sizeof(Vec3));
    h = fnv1a64(reinterpret_cast<const unsigned char*>(mesh.indices.data()),
                mesh.indices.size() * sizeof(uint32_t), h);
    const unsigned char sides = two_sided ? 2 : 1;
    return fnv1a64(&sides, 1, h);
}

}  // namespace

LightTree mesh_light_tree(const Mesh& mesh, bool two_sided) {
    std::vector<LightBounds> bounds;
    bounds.reserve(mesh.triangle_count());
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const Vec3& p0 = mesh.positions[mesh.indices[3 * t]];
        const Vec3& p1 = mesh.positions[mesh.indices[3 * t + 1]];
        const Vec3& p2 = mesh.positions[mesh.indices[3 * t + 2]];
        const Vec3 n = glm::cross(p1 - p0, p2 - p0);
        bounds.push_back(triangle_light_bounds(p0, p1, p2, n, 0.5f * glm::length(n), two_sided));
    }
    return LightTree(bounds);
}

const LightTree& LightTopologyCache::mesh_tree(const Mesh& mesh, bool two_sided) {
    const uint64_t key = geometry_key(mesh, two_sided);
    auto it = trees_.find(key);
    if (it == trees_.end()) {
        it = trees_.emplace(key, Entry{mesh_light_tree(mesh, two_sided)}).first;
        ++builds_;
    }
    it->second.used = true;
    return it->second.tree;
}

void LightTopologyCache::end_state() {
    std::erase_if(trees_, [](const auto& kv) { return !kv.second.used; });
    for (auto& [key, entry] : trees_)
        entry.used = false;
}

}  // namespace pathfarm
