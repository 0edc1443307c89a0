// With instances to move and over 4 000 baked triangles, the Embree scene keeps the baked
// triangles in a scene apart from the top level, and every query traverses both: the baked
// scene first, then the top level with what is left of the ray (embree_scene.cpp). Its answers
// must be those of one flat BVH holding every triangle. Searched over random placements of
// builtin:default's instanced meshes (the gold balls, the door, the glass ball) in front of,
// behind and inside the baked room, with random rays, segments and 8-ray packets.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/scene/load/builtin_scenes.h"
#include "tests/support/random_geometry.h"
#include "tracer-node/embree/embree_scene.h"

namespace pathfarm::baked_apart_test {
namespace {

using test::random_direction;

constexpr int kWidth = Intersector::kCoherentWidth;

Bounds3f instance_bounds(const SceneModel& scene, const Instance& inst) {
    Bounds3f b;
    for (const Vec3& p : scene.meshes[std::size_t(inst.mesh)].positions)
        b.extend(Vec3(inst.transform * Vec4(p, 1.0f)));
    return b;
}

// Moves instances of shared meshes (balls, crates, pillars) and small objects of a few
// triangles (the door, the lights, the mirror) somewhere in `room`, turned and scaled at
// random, and marks them dynamic. The walls, the lamp and the glass ball stay: over 4 000
// triangles are baked.
void scatter_instances(SceneModel& scene, const Bounds3f& room, std::mt19937& rng) {
    std::vector<int> users(scene.meshes.size(), 0);
    for (const Instance& inst : scene.instances)
        ++users[std::size_t(inst.mesh)];
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const float room_size = glm::length(room.extent());
    for (Instance& inst : scene.instances) {
        const bool shared = users[std::size_t(inst.mesh)] > 1;
        const bool small = glm::length(instance_bounds(scene, inst).extent()) < 0.25f * room_size;
        if (!shared && !(small && scene.meshes[std::size_t(inst.mesh)].triangle_count() < 100))
            continue;
        const Vec3 at = room.lower + room.extent() * Vec3(unit(rng), unit(rng), unit(rng));
        const Mat4 turn = glm::rotate(Mat4(1.0f), 6.2832f * unit(rng), random_direction(rng));
        const Vec3 centre = instance_bounds(scene, inst).center();
        inst.transform = glm::translate(Mat4(1.0f), at) * turn *
                         glm::scale(Mat4(1.0f), Vec3(0.5f + unit(rng))) *
                         glm::translate(Mat4(1.0f), -centre) * inst.transform;
        inst.dynamic = true;
    }
}

// The same triangles in one BVH: every instance its own mesh, none dynamic, so all are baked
// into the top level.
SceneModel flattened(const SceneModel& scene) {
    SceneModel flat = scene;
    flat.meshes.clear();
    for (Instance& inst : flat.instances) {
        flat.meshes.push_back(scene.meshes[std::size_t(inst.mesh)]);
        inst.mesh = int(flat.meshes.size()) - 1;
        inst.dynamic = false;
    }
    return flat;
}

// The flat scene traces instanced meshes in world space, the split one in object space, so
// their answers may differ by rounding: t within a relative 1e-4 (and 1e-4 of the room's
// 10-metre scale), and a hit that one of them finds and the other does not within 1e-4 of a
// triangle's edge or of the segment's end.
bool near_edge(const Hit& h) { return std::min({h.u, h.v, 1.0f - h.u - h.v}) < 1e-4f; }
bool same_t(float a, float b) { return std::abs(a - b) <= 1e-4f * std::max(a, b) + 1e-4f; }

struct Tally {
    int rays = 0, on_moved = 0, on_baked = 0, misses = 0, rounding = 0, mismatches = 0;
};

// One closest-hit answer of the split scene against the flat one's.
void compare_hit(const SceneModel& scene, const Ray& ray, bool found, const Hit& hit,
                 bool found_flat, const Hit& flat, Tally& t) {
    ++t.rays;
    if (!found_flat)
        ++t.misses;
    else if (scene.instances[flat.instance].dynamic)
        ++t.on_moved;
    else
        ++t.on_baked;
    if (found == found_flat && (!found || (hit.instance == flat.instance && hit.prim == flat.prim &&
                                           same_t(hit.t, flat.t))))
        return;
    const bool rounding = found != found_flat
                              ? near_edge(found ? hit : flat)
                              : same_t(hit.t, flat.t) || near_edge(hit) || near_edge(flat);
    if (rounding) {
        ++t.rounding;
    } else if (++t.mismatches <= 3) {
        ADD_FAILURE() << "ray from (" << ray.o.x << ", " << ray.o.y << ", " << ray.o.z << "), tmax "
                      << ray.tmax << ": split found " << found << " instance " << hit.instance
                      << " t " << hit.t << "; flat found " << found_flat << " instance "
                      << flat.instance << " t " << flat.t;
    }
}

Tally compare_scenes(const SceneModel& scene, const Bounds3f& box, int rays, uint32_t seed) {
    Tally t;
    auto split = tracer::EmbreeScene::build(scene, 2);
    const SceneModel flat_scene = flattened(scene);
    auto flat = tracer::EmbreeScene::build(flat_scene, 2);
    EXPECT_TRUE(split.ok() && flat.ok());
    if (!split.ok() || !flat.ok()) return t;
    EXPECT_TRUE((*split)->baked_apart()) << "the search needs the layout it tests";
    EXPECT_FALSE((*flat)->baked_apart());
    const Vec3 size = box.extent();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    auto random_ray = [&] {
        const Vec3 o = box.lower + size * Vec3(unit(rng), unit(rng), unit(rng));
        // Half of the rays aim at a moved instance, so that its hits stand before baked ones.
        Vec3 d = random_direction(rng);
        const Instance& inst = scene.instances[rng() % scene.instances.size()];
        if (inst.dynamic && unit(rng) < 0.5f)
            d = glm::normalize(Vec3(inst.transform[3]) + 0.3f * random_direction(rng) - o);
        const float tmax = rng() % 3 == 0 ? unit(rng) * glm::length(size) : kInfinity;
        return Ray{o, d, tmax};
    };
    for (int r = 0; r < rays; ++r) {
        const Ray ray = random_ray();
        Hit hit, ref;
        const bool found = (*split)->intersect(ray, hit);
        const bool found_flat = (*flat)->intersect(ray, ref);
        compare_hit(scene, ray, found, hit, found_flat, ref, t);
        // A shadow ray over the same segment: occluded where the flat scene finds a hit.
        if ((*split)->occluded(ray) != found_flat && !(found_flat && near_edge(ref)) &&
            !(found_flat && same_t(ref.t, ray.tmax)) && ++t.mismatches <= 3)
            ADD_FAILURE() << "segment " << r << ": occluded " << !found_flat
                          << " in the split scene";
    }
    for (int p = 0; p < rays / kWidth; ++p) {
        const int count = 1 + int(rng() % kWidth);
        Ray packet[kWidth];
        for (int i = 0; i < count; ++i)
            packet[i] = random_ray();
        Hit hits[kWidth];
        bool found[kWidth];
        (*split)->intersect_coherent(packet, count, hits, found);
        for (int i = 0; i < count; ++i) {
            Hit ref;
            const bool found_flat = (*flat)->intersect(packet[i], ref);
            compare_hit(scene, packet[i], found[i], hits[i], found_flat, ref, t);
        }
    }
    return t;
}

TEST(BakedApart, TheBakedSceneAndTheTopLevelAnswerAsOneFlatScene) {
    for (uint32_t trial = 0; trial < 6; ++trial) {
        std::mt19937 rng(100 + trial);
        SceneModel scene = make_default_scene();
        const Bounds3f room = world_bounds(scene);
        scatter_instances(scene, room, rng);
        const Tally t = compare_scenes(scene, room, 4000, trial);
        std::printf(
            "trial %u: %d rays, %d on moved instances, %d on baked triangles, %d misses, "
            "%d within rounding\n",
            trial, t.rays, t.on_moved, t.on_baked, t.misses, t.rounding);
        EXPECT_EQ(t.mismatches, 0) << "trial " << trial;
        EXPECT_LE(t.rounding, t.rays / 500) << "trial " << trial;
        // The search must have seen moved instances in front of baked triangles, and both alone.
        EXPECT_GT(t.on_moved, t.rays / 20) << "trial " << trial;
        EXPECT_GT(t.on_baked, t.rays / 4) << "trial " << trial;
    }
}

}  // namespace
}  // namespace pathfarm::baked_apart_test
