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

// Edges are grouped by their lower vertex (a counting sort, no hashing: a rolling ball's
// components are found anew every frame its rounding welds other vertices) and, within a
// vertex's few edges, by the upper one.
std::vector<std::vector<uint32_t>> closed_components(const Welding& welding) {
    const std::vector<uint32_t>& ids = welding.corner_ids;
    const std::size_t n = ids.size() / 3;
    UnionFind components(n);
    std::vector<bool> degenerate(n, false);
    const uint32_t vertices = ids.empty() ? 0u : *std::max_element(ids.begin(), ids.end()) + 1u;
    std::vector<uint32_t> first(std::size_t(vertices) + 1, 0u);  // edges by lower vertex
    const auto each_edge = [&](auto&& visit) {
        for (uint32_t t = 0; t < n; ++t) {
            const uint32_t v[3] = {ids[3 * t], ids[3 * t + 1], ids[3 * t + 2]};
            if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
                degenerate[t] = true;
                continue;
            }
            for (int k = 0; k < 3; ++k)
                visit(std::min(v[k], v[(k + 1) % 3]), std::max(v[k], v[(k + 1) % 3]), t);
        }
    };
    each_edge([&](uint32_t a, uint32_t, uint32_t) { ++first[a + 1]; });
    std::partial_sum(first.begin(), first.end(), first.begin());
    struct Use {
        uint32_t upper, triangle;
    };
    std::vector<Use> uses(first.back());
    std::vector<uint32_t> fill(first.begin(), first.end() - 1);
    each_edge([&](uint32_t a, uint32_t b, uint32_t t) { uses[fill[a]++] = {b, t}; });
    std::vector<uint8_t> open(n, 0);  // by component root, once every edge is counted
    std::vector<uint32_t> open_at;    // a triangle of each edge not used exactly twice
    for (uint32_t a = 0; a < vertices; ++a) {
        const auto begin = uses.begin() + first[a], end = uses.begin() + first[a + 1];
        std::sort(begin, end, [](const Use& x, const Use& y) {
            return x.upper != y.upper ? x.upper < y.upper : x.triangle < y.triangle;
        });
        for (auto group = begin; group != end;) {
            auto next = group + 1;
            for (; next != end && next->upper == group->upper; ++next)
                components.unite(next->triangle, group->triangle);
            if (next - group != 2) open_at.push_back(group->triangle);
            group = next;
        }
    }
    for (const uint32_t t : open_at)
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
