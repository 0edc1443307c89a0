// Diffing per-frame acceleration structures into commit ops.
#include "coordinator/commit/bvh_ops.h"

#include <cstring>

namespace pathfarm::coord {
namespace {

bool same_node(const BvhNode& a, const BvhNode& b) {
    return std::memcmp(&a, &b, sizeof(BvhNode)) == 0;
}

SetMeshBvh mesh_op(uint32_t id, const Bvh* old, const Bvh& now) {
    SetMeshBvh op{id, uint32_t(now.nodes.size()), 0, {}, {}};
    const bool topology =
        !old || old->nodes.size() != now.nodes.size() || old->prim_indices != now.prim_indices;
    if (topology) {
        op.nodes = now.nodes;
        op.prim_indices = now.prim_indices;
        return op;
    }
    std::size_t first = 0, end = now.nodes.size();
    while (first < end && same_node(old->nodes[first], now.nodes[first]))
        ++first;
    while (end > first && same_node(old->nodes[end - 1], now.nodes[end - 1]))
        --end;
    op.first_node = uint32_t(first);
    op.nodes.assign(now.nodes.begin() + std::ptrdiff_t(first),
                    now.nodes.begin() + std::ptrdiff_t(end));
    return op;
}

std::vector<uint32_t> instance_ids(const AccelSnapshot& s) {
    std::vector<uint32_t> ids;
    for (const InstanceAccel& i : s.instances)
        ids.push_back(i.id);
    return ids;
}

bool same_top(const AccelSnapshot& a, const AccelSnapshot& b) {
    return a.top.nodes.size() == b.top.nodes.size() && a.top.prim_indices == b.top.prim_indices &&
           instance_ids(a) == instance_ids(b) &&
           std::memcmp(a.top.nodes.data(), b.top.nodes.data(),
                       a.top.nodes.size() * sizeof(BvhNode)) == 0;
}

}  // namespace

std::vector<CommitOp> build_bvh_ops(const AccelSnapshot* previous, const AccelSnapshot& next) {
    std::vector<CommitOp> ops;
    for (const auto& [id, mesh] : next.meshes) {
        const MeshAccel* old = nullptr;
        if (previous) {
            const auto it = previous->meshes.find(id);
            if (it != previous->meshes.end()) {
                if (it->second == mesh) continue;  // the same shared structure: unchanged
                old = it->second.get();
            }
        }
        SetMeshBvh op = mesh_op(id, old ? &old->bvh : nullptr, mesh->bvh);
        if (!op.nodes.empty() || !op.prim_indices.empty()) ops.push_back(std::move(op));
    }
    if (!previous || !same_top(*previous, next))
        ops.push_back(SetTopLevelBvh{instance_ids(next), next.top.nodes, next.top.prim_indices});
    return ops;
}

DerivedBvh derived_bvh(const AccelSnapshot& s) {
    DerivedBvh d;
    for (const auto& [id, mesh] : s.meshes)
        d.meshes.emplace(id, BvhData{mesh->bvh.nodes, mesh->bvh.prim_indices});
    d.top_instances = instance_ids(s);
    d.top = BvhData{s.top.nodes, s.top.prim_indices};
    return d;
}

}  // namespace pathfarm::coord
