// closed_components (closed_surfaces.h) against a brute-force reading of its contract on random
// triangle soups over few vertices (edges used once, twice or more, degenerate triangles,
// several components) and on a welded cube, closed until a triangle is taken out.
#include "common/render/closed_surfaces.h"

#include <map>
#include <random>

#include <gtest/gtest.h>

#include "common/scene/load/procedural_mesh.h"

namespace pathfarm {
namespace {

// The contract, the slow way: triangles joined when they share an edge (pairwise), a
// component closed when each of its edges is used by exactly two of its triangles.
std::vector<std::vector<uint32_t>> reference(const std::vector<uint32_t>& ids) {
    const std::size_t n = ids.size() / 3;
    const auto degenerate = [&](std::size_t t) {
        return ids[3 * t] == ids[3 * t + 1] || ids[3 * t + 1] == ids[3 * t + 2] ||
               ids[3 * t] == ids[3 * t + 2];
    };
    const auto edge = [&](std::size_t t, int k) {
        const uint32_t a = ids[3 * t + std::size_t(k)], b = ids[3 * t + std::size_t(k + 1) % 3];
        return std::pair(std::min(a, b), std::max(a, b));
    };
    std::vector<std::size_t> label(n);
    for (std::size_t t = 0; t < n; ++t)
        label[t] = t;
    for (bool changed = true; changed;) {  // flood labels to the minimum over shared edges
        changed = false;
        for (std::size_t s = 0; s < n; ++s)
            for (std::size_t t = 0; t < n; ++t) {
                if (s == t || degenerate(s) || degenerate(t) || label[t] <= label[s]) continue;
                bool shared = false;
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j)
                        shared = shared || edge(s, i) == edge(t, j);
                if (shared) {
                    label[t] = label[s];
                    changed = true;
                }
            }
    }
    std::map<std::pair<uint32_t, uint32_t>, int> uses;
    for (std::size_t t = 0; t < n; ++t)
        for (int k = 0; !degenerate(t) && k < 3; ++k)
            ++uses[edge(t, k)];
    std::map<std::size_t, bool> open;
    for (std::size_t t = 0; t < n; ++t)
        for (int k = 0; !degenerate(t) && k < 3; ++k)
            open[label[t]] = open[label[t]] || uses[edge(t, k)] != 2;
    std::vector<std::vector<uint32_t>> closed;
    std::map<std::size_t, std::size_t> index;
    for (std::size_t t = 0; t < n; ++t) {
        if (degenerate(t) || open[label[t]]) continue;
        if (!index.count(label[t])) {
            index[label[t]] = closed.size();
            closed.emplace_back();
        }
        closed[index[label[t]]].push_back(uint32_t(t));
    }
    return closed;
}

Welding of_ids(std::vector<uint32_t> ids) {
    Welding w;
    w.corner_ids = std::move(ids);
    return w;
}

TEST(ClosedSurfaces, RandomSoupsMatchTheBruteForceReading) {
    std::mt19937 rng(5);
    int closed_found = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const uint32_t vertices = 3 + rng() % 8;
        std::vector<uint32_t> ids;
        // Tetrahedra (closed) among random triangles; vertex ids shuffled so neither order
        // nor numbering helps.
        const int tetrahedra = int(rng() % 3), loose = int(rng() % 12);
        for (int i = 0; i < tetrahedra; ++i) {
            uint32_t v[4];
            for (uint32_t& x : v)
                x = rng() % vertices;
            for (const auto& f : {std::array{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}})
                for (int k : f)
                    ids.push_back(v[k]);
        }
        for (int i = 0; i < 3 * loose; ++i)
            ids.push_back(rng() % vertices);
        std::vector<uint32_t> order(ids.size() / 3);
        for (uint32_t t = 0; t < order.size(); ++t)
            order[t] = t;
        std::shuffle(order.begin(), order.end(), rng);
        std::vector<uint32_t> shuffled;
        for (uint32_t t : order)
            for (int k = 0; k < 3; ++k)
                shuffled.push_back(ids[3 * t + std::size_t(k)]);
        const auto expected = reference(shuffled);
        closed_found += int(!expected.empty());
        EXPECT_EQ(closed_components(of_ids(shuffled)), expected) << "trial " << trial;
    }
    EXPECT_GT(closed_found, 50) << "the soups must hold closed components too";
}

TEST(ClosedSurfaces, AWeldedCubeIsClosedUntilATriangleIsTakenOut) {
    const Mesh cube = make_unit_cube(0);
    std::vector<Vec3> tris;
    for (uint32_t v : cube.indices)
        tris.push_back(cube.positions[v]);
    Welding w = weld(tris);
    const auto closed = closed_components(w);
    EXPECT_EQ(closed, reference(w.corner_ids));
    ASSERT_EQ(closed.size(), 1u);
    std::size_t kept = 0;
    for (std::size_t t = 0; t < tris.size() / 3; ++t) {
        const uint32_t* v = &w.corner_ids[3 * t];
        kept += v[0] != v[1] && v[1] != v[2] && v[0] != v[2];
    }
    EXPECT_EQ(closed[0].size(), kept) << "every non-degenerate triangle";
    w.corner_ids.resize(w.corner_ids.size() - 3);
    EXPECT_TRUE(closed_components(w).empty());
}

}  // namespace
}  // namespace pathfarm
