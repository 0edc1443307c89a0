// Packets of camera rays (Intersector::intersect_coherent, Embree's rtcIntersect8 with the
// coherent flag) answer every ray as intersect() answers it alone, bit for bit: the frame loop
// traces camera rays a packet at a time, and a pixel's value must not depend on which of its
// neighbours shared its packet (a pixel with extra samples shares fewer: extra_samples_test).
// Searched over random packets, from a tight bundle to rays that share nothing, with 1 to 8
// lanes and finite or infinite ends, in scenes with baked, instanced and alpha-tested meshes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/scene_loader.h"
#include "tests/support/random_geometry.h"
#include "tests/support/test_env.h"
#include "tracer-node/embree/embree_scene.h"

namespace pathfarm::coherent_rays_test {
namespace {

using test::random_direction;

constexpr int kWidth = Intersector::kCoherentWidth;

bool same_hit(const Hit& a, const Hit& b) {
    return std::memcmp(&a.t, &b.t, sizeof(float)) == 0 && a.instance == b.instance &&
           a.prim == b.prim && std::memcmp(&a.u, &b.u, sizeof(float)) == 0 &&
           std::memcmp(&a.v, &b.v, sizeof(float)) == 0;
}

// Two triangles at the same distance (an edge or corner both share, or faces that touch): the
// packet's arithmetic, an ulp from the single ray's, may pick either.
bool tie(const Hit& a, const Hit& b) {
    return std::abs(a.t - b.t) <= 1e-6f * std::max(a.t, b.t) + 1e-7f;
}

struct Tally {
    int packets = 0, rays = 0, hits = 0, misses = 0, ties = 0, mismatches = 0;
};

// `packets` random packets in `scene`, each compared lane by lane with intersect().
Tally compare_packets(const SceneModel& scene, int packets, uint32_t seed) {
    auto built = tracer::EmbreeScene::build(scene, 2);
    EXPECT_TRUE(built.ok()) << built.error().message;
    Tally tally;
    if (!built.ok()) return tally;
    const tracer::EmbreeScene& kernel = **built;
    const Bounds3f box = world_bounds(scene);
    const Vec3 size = box.upper - box.lower;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const float spreads[] = {0.0f, 1e-4f, 3e-3f, 0.05f, 0.5f, 4.0f};
    for (int p = 0; p < packets; ++p) {
        // A centre inside the scene's bounds (a little outside too), a direction, and lanes
        // spread about both by up to `spread` (radians, and that fraction of the scene).
        const Vec3 centre =
            box.lower +
            size * Vec3(unit(rng) * 1.2f - 0.1f, unit(rng) * 1.2f - 0.1f, unit(rng) * 1.2f - 0.1f);
        const Vec3 dir = random_direction(rng);
        const float spread = spreads[rng() % std::size(spreads)];
        const int count = 1 + int(rng() % kWidth);
        Ray rays[kWidth];
        for (int i = 0; i < count; ++i) {
            const Vec3 o = centre + spread * 0.05f * size * (random_direction(rng) * unit(rng));
            const Vec3 d = glm::normalize(dir + spread * random_direction(rng));
            const float tmax = rng() % 3 == 0 ? unit(rng) * glm::length(size) : kInfinity;
            rays[i] = Ray{o, d, tmax};
        }
        Hit packed[kWidth];
        bool found[kWidth];
        kernel.intersect_coherent(rays, count, packed, found);
        ++tally.packets;
        for (int i = 0; i < count; ++i) {
            Hit alone;
            const bool found_alone = kernel.intersect(rays[i], alone);
            ++tally.rays;
            (found_alone ? tally.hits : tally.misses) += 1;
            if (found[i] == found_alone && (!found_alone || same_hit(packed[i], alone))) continue;
            if (found[i] && found_alone && tie(packed[i], alone)) {
                ++tally.ties;
            } else {
                if (++tally.mismatches <= 3)
                    ADD_FAILURE() << scene.name << ": packet " << p << " lane " << i << " of "
                                  << count << " (spread " << spread << "): found " << found[i]
                                  << " t " << packed[i].t << " prim " << packed[i].prim
                                  << "; alone found " << found_alone << " t " << alone.t << " prim "
                                  << alone.prim;
            }
        }
    }
    return tally;
}

void expect_packets_agree(const SceneModel& scene, int packets, uint32_t seed) {
    const Tally t = compare_packets(scene, packets, seed);
    EXPECT_EQ(t.mismatches, 0) << scene.name << ": of " << t.rays << " rays";
    EXPECT_LE(t.ties, t.hits / 100) << scene.name << ": of " << t.hits << " hits";
    std::printf("%s: %d packets, %d rays, %d hits, %d ties\n", scene.name.c_str(), t.packets,
                t.rays, t.hits, t.ties);
    // The search must have looked at both answers in quantity.
    EXPECT_GT(t.hits, t.rays / 4) << scene.name;
    EXPECT_GT(t.misses, 0) << scene.name;
}

TEST(CoherentRays, PacketsAnswerAsSingleRaysInTheDefaultScene) {
    SceneModel scene = make_default_scene();
    expect_packets_agree(scene, 3000, 1);
    // The same meshes instanced (each one dynamic, so none is baked): two-level traversal.
    for (Instance& inst : scene.instances)
        inst.dynamic = true;
    expect_packets_agree(scene, 3000, 2);
}

TEST(CoherentRays, PacketsAnswerAsSingleRaysWithGlassAndManyLights) {
    for (const char* name : {"glass", "many-lights", "cornell"}) {
        auto scene = make_builtin_scene(name);
        ASSERT_TRUE(scene.ok()) << name;
        expect_packets_agree(*scene, 2000, 3);
    }
}

// Alpha-tested geometry: the filter runs per lane of a packet (alpha_filter's N lanes).
TEST(CoherentRays, PacketsAnswerAsSingleRaysThroughAlphaTestedSurfaces) {
    PF_REQUIRE_SCENES(dir);
    auto scene = load_scene(dir + "/alpha-blend-mode-test/AlphaBlendModeTest.gltf");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    expect_packets_agree(*scene, 3000, 4);
}

TEST(CoherentRays, PacketsAnswerAsSingleRaysInSponza) {
    PF_REQUIRE_SCENES(dir);
    auto scene = load_scene(dir + "/dabrovic-sponza/sponza.obj");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    expect_packets_agree(*scene, 2000, 5);
}

}  // namespace
}  // namespace pathfarm::coherent_rays_test
