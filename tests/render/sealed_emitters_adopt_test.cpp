// Adopting the previous analysis when instances move or meshes deform (SealedEmitters::adopt,
// what a tracer does every frame a ball rolls, a door swings or a skinned figure walks) must
// give what a new analysis of the new state gives. Searched over random moves of cubes, a sphere,
// emitters inside and outside them and the walls of a closed room, on a grid coarse enough that
// corners often meet (surfaces that join: only a new analysis may see them) and with a sphere whose
// pole vertices meet or not depending on where it is placed.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <random>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/math/transform.h"
#include "common/render/sealed_emitters.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_builder.h"

namespace pathfarm {
namespace {

struct Movable {
    std::vector<std::size_t> instances;  // moved together (a cube and the lamp inside it)
    std::vector<Mat4> local;             // each one's placement relative to the group
    bool wall = false;
};

struct Playground {
    SceneModel scene;
    std::vector<Movable> movables;
    std::vector<int> deformable;                // meshes: the sphere, the cube, the lamp
    std::vector<std::vector<Vec3>> rest_shape;  // their vertices as made
};

// Where the room is: far enough from the origin that the sphere's pole vertices, apart in its
// own space, meet in the world at some of its places and not at others.
const Vec3 kRoom(2.5f, 0.0f, 2.5f);

// A closed room of six walls (instances sharing their corners), cubes, a lantern (a cube with a
// lamp inside), a sphere with a lamp inside, free lamps and a glass cube.
Playground make_playground() {
    SceneBuilder b("sealed-moves");
    const int wall = b.add_material(make_lambert("wall", Rgb(0.5f)));
    const int lamp = b.add_material(make_emitter("lamp", Rgb(5.0f)));
    Material glass_material = make_lambert("glass", Rgb(0.9f));
    glass_material.transmission_factor = 1.0f;
    const int glass = b.add_material(glass_material);
    Playground p;
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a)
        for (float s : {-2.0f, 2.0f}) {
            const Vec3 u = 2.0f * axes[(a + 1) % 3], v = 2.0f * axes[(a + 2) % 3];
            const std::size_t i = std::size_t(b.add_instance(
                b.add_mesh(make_quad(s * axes[a], s > 0 ? u : v, s > 0 ? v : u, wall)),
                Mat4(1.0f)));
            p.movables.push_back({{i}, {Mat4(1.0f)}, true});
        }
    const int cube = b.add_mesh(make_unit_cube(wall));
    const int small_lamp = b.add_mesh(make_quad(Vec3(0.0f), {0.1f, 0, 0}, {0, 0, 0.1f}, lamp));
    const Mat4 shrink = glm::scale(Mat4(1.0f), Vec3(0.5f));
    auto add = [&](std::vector<std::pair<int, Mat4>> parts) {
        Movable m;
        for (const auto& [mesh, local] : parts) {
            m.instances.push_back(std::size_t(b.add_instance(mesh, local)));
            m.local.push_back(local);
        }
        p.movables.push_back(m);
    };
    for (int k = 0; k < 3; ++k)
        add({{cube, Mat4(1.0f)}});
    add({{cube, Mat4(1.0f)}, {small_lamp, shrink}});  // lantern
    const int sphere = b.add_mesh(make_sphere(0.35f, 8, 16, wall));
    add({{sphere, Mat4(1.0f)}, {small_lamp, shrink}});
    p.deformable = {sphere, cube, small_lamp};
    for (int k = 0; k < 2; ++k)
        add({{small_lamp, Mat4(1.0f)}});
    add({{b.add_mesh(make_unit_cube(glass)), Mat4(1.0f)}});
    p.scene = b.finish();
    for (Instance& inst : p.scene.instances)
        inst.transform = glm::translate(Mat4(1.0f), kRoom) * inst.transform;
    for (int m : p.deformable)
        p.rest_shape.push_back(p.scene.meshes[std::size_t(m)].positions);
    return p;
}

// A deformation (what skinning does to a mesh every frame): the rest shape stretched per axis,
// now and then dented at one vertex, or back to rest.
void deform(std::mt19937& rng, Playground& p) {
    const std::size_t k = rng() % p.deformable.size();
    std::vector<Vec3>& positions = p.scene.meshes[std::size_t(p.deformable[k])].positions;
    std::uniform_real_distribution<float> stretch(0.7f, 1.3f);
    const Vec3 s = rng() % 4 == 0 ? Vec3(1.0f) : Vec3(stretch(rng), stretch(rng), stretch(rng));
    for (std::size_t v = 0; v < positions.size(); ++v)
        positions[v] = p.rest_shape[k][v] * s;
    if (rng() % 3 == 0) positions[rng() % positions.size()] *= 0.8f;
}

// Where a group goes: mostly on a 0.5 grid (corners meet other cubes' and the room's), at
// times anywhere, at times turned a quarter; a wall moves off its place and back.
Mat4 random_place(std::mt19937& rng, bool wall) {
    std::uniform_int_distribution<int> grid(-3, 3), kind(0, 5);
    std::uniform_real_distribution<float> any(-1.5f, 1.5f);
    if (wall)
        return kind(rng) < 3
                   ? Mat4(1.0f)
                   : glm::translate(Mat4(1.0f), Vec3(0.0f, 0.5f * float(grid(rng)), 0.0f));
    const int k = kind(rng);
    Vec3 at(0.5f * float(grid(rng)), 0.5f * float(grid(rng)), 0.5f * float(grid(rng)));
    if (k == 0) at = Vec3(any(rng), any(rng), any(rng));
    Mat4 m = glm::translate(Mat4(1.0f), at);
    if (k == 1) m = glm::rotate(m, glm::radians(90.0f), Vec3(0, 1, 0));
    return m;
}

std::vector<Vec3> viewers(const Playground& p) {
    std::vector<Vec3> out = {kRoom + Vec3(0.1f, 0.2f, 0.3f), kRoom + Vec3(10.0f, 0.5f, 0.0f),
                             kRoom + Vec3(1.9f, -1.9f, 1.9f)};
    for (const Movable& m : p.movables)
        if (!m.wall)  // inside each group, beside its lamp if it has one
            out.push_back(transform_point(p.scene.instances[m.instances[0]].transform,
                                          Vec3(0.05f, 0.1f, -0.05f)));
    return out;
}

TEST(SealedEmittersAdopt, MovedInstancesGiveWhatANewAnalysisGives) {
    Playground p = make_playground();
    std::mt19937 rng(20261204);
    auto kept = std::make_unique<SealedEmitters>(p.scene);
    int adopted = 0, analysed = 0, culled_in_room = 0, enclosures_changed = 0;
    int adopted_deformed = 0;
    std::size_t last_enclosures = kept->enclosure_count();
    constexpr int kSteps = 400;
    for (int step = 0; step < kSteps; ++step) {
        std::uniform_int_distribution<std::size_t> pick(0, p.movables.size() - 1);
        const int moves = int(rng() % 4);
        const bool deformed = moves < 2;  // some steps deform alone, some with moves
        if (deformed) deform(rng, p);
        for (int k = 0; k < moves; ++k) {
            const Movable& m = p.movables[pick(rng)];
            const Mat4 place = glm::translate(Mat4(1.0f), kRoom) * random_place(rng, m.wall);
            for (std::size_t j = 0; j < m.instances.size(); ++j)
                p.scene.instances[m.instances[j]].transform = place * m.local[j];
        }
        if (kept->adopt(p.scene)) {
            ++adopted;
            adopted_deformed += deformed;
        } else {
            ++analysed;
            kept = std::make_unique<SealedEmitters>(p.scene);
        }
        const SealedEmitters fresh(p.scene);
        ASSERT_EQ(kept->enclosure_count(), fresh.enclosure_count()) << "step " << step;
        enclosures_changed += fresh.enclosure_count() != last_enclosures;
        last_enclosures = fresh.enclosure_count();
        for (const Vec3& v : viewers(p))
            ASSERT_EQ(kept->culled(v), fresh.culled(v))
                << "step " << step << ", viewer " << v.x << "," << v.y << "," << v.z;
        // In the room: a lamp culled means a cube or the sphere closed around it.
        const std::vector<bool> in_room = fresh.culled(viewers(p)[0]);
        culled_in_room += std::find(in_room.begin(), in_room.end(), true) != in_room.end();
    }
    // The search covered what it is for: most steps adopted, some analysed anew (surfaces
    // that met), lamps culled and enclosures appearing and going.
    EXPECT_GT(adopted, kSteps / 3);
    EXPECT_GT(adopted_deformed, kSteps / 8);
    EXPECT_GT(analysed, 10);
    EXPECT_GT(culled_in_room, kSteps / 4);
    EXPECT_GT(enclosures_changed, 20);
    std::printf(
        "adopted %d (%d with a mesh deformed), analysed anew %d, a lamp culled in the room %d, "
        "enclosure count changed %d\n",
        adopted, adopted_deformed, analysed, culled_in_room, enclosures_changed);
}

// What the demo does every frame: builtin:default's gold ball rolls to and fro. Each state is
// adopted (the ball's vertices are its own), returning to earlier places included.
TEST(SealedEmittersAdopt, ARollingBallIsAdoptedEveryFrame) {
    const SceneModel scene = make_default_scene();
    std::size_t ball = scene.instances.size();
    for (std::size_t i = 0; i < scene.instances.size(); ++i)
        if (scene.nodes[std::size_t(scene.instances[i].node)].name == "gold-ball") ball = i;
    ASSERT_LT(ball, scene.instances.size());
    SealedEmitters kept(scene);
    for (int f = 1; f <= 24; ++f) {
        SceneModel moved = scene;
        const float x = 0.05f * float(f <= 12 ? f : 24 - f);  // there and back
        moved.instances[ball].transform =
            glm::translate(Mat4(1.0f), Vec3(x, 0.0f, 0.0f)) * moved.instances[ball].transform;
        ASSERT_TRUE(kept.adopt(moved)) << "frame " << f;
        const SealedEmitters fresh(moved);
        const Vec3 eye = transform_point(moved.cameras.at(0).camera_to_world, Vec3(0.0f));
        EXPECT_EQ(kept.culled(eye), fresh.culled(eye)) << "frame " << f;
        EXPECT_EQ(kept.enclosure_count(), fresh.enclosure_count()) << "frame " << f;
    }
}

}  // namespace
}  // namespace pathfarm
