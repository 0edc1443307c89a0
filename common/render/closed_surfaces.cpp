// Edge counting over welded vertices, with a union-find over the triangles sharing an edge.
#include "common/render/closed_surfaces.h"

#include <algorithm>
#include <bit>
#include <numeric>

namespace pathfarm {
namespace {

struct UnionFind {
    std::vector<uint32_t> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    uint32_t find(uint32_t a) {
        while (parent[a] != a)
            a = parent[a] = parent[parent[a]];
        return a;
    }
    void unite(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

}  // namespace

WeldKey weld_key(const Vec3& p) {
    auto bits = [](float f) { return std::bit_cast<uint32_t>(f == 0.0f ? 0.0f : f); };
    return {bits(p.x), bits(p.y), bits(p.z)};
}

Welding weld(const std::vector<Vec3>& tris) {
    Welding w;
    w.corner_ids.resize(tris.size());
    w.ids.reserve(tris.size() / 2);
    for (std::size_t i = 0; i < tris.size(); ++i) {
        const auto [it, added] = w.ids.emplace(weld_key(tris[i]), uint32_t(w.keys.size()));
        if (added) w.keys.push_back(it->first);
        w.corner_ids[i] = it->second;
    }
    return w;
}

std::vector<std::vector<uint32_t>> closed_components(const Welding& welding) {
    const std::vector<uint32_t>& ids = welding.corner_ids;
    const std::size_t n = ids.size() / 3;
    UnionFind components(n);
    std::vector<bool> degenerate(n, false);
    // Undirected edge (its vertex ids) -> (triangles using it, one of them).
    std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> edges;
    edges.reserve(3 * n / 2);
    for (uint32_t t = 0; t < n; ++t) {
        const uint32_t v[3] = {ids[3 * t], ids[3 * t + 1], ids[3 * t + 2]};
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
            degenerate[t] = true;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = std::min(v[k], v[(k + 1) % 3]), b = std::max(v[k], v[(k + 1) % 3]);
            auto [it, added] = edges.try_emplace((uint64_t(a) << 32) | b, 0u, t);
            ++it->second.first;
            if (!added) components.unite(t, it->second.second);
        }
    }
    std::vector<uint8_t> open(n, 0);  // by component root
    for (const auto& [edge, use] : edges)
        if (use.first != 2) open[components.find(use.second)] = 1;
    std::vector<std::vector<uint32_t>> closed;
    std::vector<uint32_t> index_of_root(n, UINT32_MAX);
    for (uint32_t t = 0; t < n; ++t) {
        if (degenerate[t]) continue;
        const uint32_t root = components.find(t);
        if (open[root]) continue;
        if (index_of_root[root] == UINT32_MAX) {
            index_of_root[root] = uint32_t(closed.size());
            closed.emplace_back();
        }
        closed[index_of_root[root]].push_back(t);
    }
    return closed;
}

}  // namespace pathfarm
