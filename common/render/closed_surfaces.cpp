// Edge counting over welded vertices, with a union-find over the triangles sharing an edge.
#include "common/render/closed_surfaces.h"

#include <algorithm>
#include <bit>
#include <numeric>
#include <tuple>

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
    const std::size_t n = tris.size();
    std::vector<WeldKey> keys(n);
    for (std::size_t i = 0; i < n; ++i)
        keys[i] = weld_key(tris[i]);
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        const WeldKey &ka = keys[a], &kb = keys[b];
        return std::tie(ka.x, ka.y, ka.z) < std::tie(kb.x, kb.y, kb.z);
    });
    // Corners of one position share the first one's index as their group; ids are then given
    // in order of first use.
    std::vector<uint32_t> group(n);
    for (std::size_t r = 0; r < n; ++r)
        group[order[r]] =
            r > 0 && keys[order[r]] == keys[order[r - 1]] ? group[order[r - 1]] : order[r];
    Welding w;
    w.corner_ids.resize(n);
    std::vector<uint32_t> id_of_group(n, UINT32_MAX);
    for (std::size_t c = 0; c < n; ++c) {
        uint32_t& id = id_of_group[group[c]];
        if (id == UINT32_MAX) {
            id = uint32_t(w.keys.size());
            w.keys.push_back(keys[c]);
        }
        w.corner_ids[c] = id;
    }
    return w;
}

std::vector<std::vector<uint32_t>> closed_components(const Welding& welding) {
    const std::vector<uint32_t>& ids = welding.corner_ids;
    const std::size_t n = ids.size() / 3;
    UnionFind components(n);
    std::vector<bool> degenerate(n, false);
    // Every use of an undirected edge (its vertex ids) by a triangle, sorted so an edge's
    // uses are neighbours.
    std::vector<std::pair<uint64_t, uint32_t>> uses;
    uses.reserve(3 * n);
    for (uint32_t t = 0; t < n; ++t) {
        const uint32_t v[3] = {ids[3 * t], ids[3 * t + 1], ids[3 * t + 2]};
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
            degenerate[t] = true;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = std::min(v[k], v[(k + 1) % 3]), b = std::max(v[k], v[(k + 1) % 3]);
            uses.emplace_back((uint64_t(a) << 32) | b, t);
        }
    }
    std::sort(uses.begin(), uses.end());
    std::vector<uint32_t> open_edge_triangles;
    for (std::size_t r = 0; r < uses.size();) {
        std::size_t end = r + 1;
        for (; end < uses.size() && uses[end].first == uses[r].first; ++end)
            components.unite(uses[end].second, uses[r].second);
        if (end - r != 2) open_edge_triangles.push_back(uses[r].second);
        r = end;
    }
    std::vector<uint8_t> open(n, 0);  // by component root
    for (uint32_t t : open_edge_triangles)
        open[components.find(t)] = 1;
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
