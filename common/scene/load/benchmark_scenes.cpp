// Built-in scenes for the benchmarks (bench/time_vs_error.py, bench/skip_bench.py), each made to
// stress one thing: builtin:glass (specular chains: glass, absorbing glass, a mirror, polished
// metal under one small light), builtin:many-lights (a room lit only by 1024 small emissive
// quads of different colours and strengths: light selection) and builtin:sealed-lights (the
// camera's room lit by one lamp, next to a closed room holding those 1024 panels: emitters
// that cannot contribute).
#include <glm/gtc/matrix_transform.hpp>

#include "common/base/hash.h"
#include "common/math/transform.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_builder.h"

namespace pathfarm {
namespace {

// A 4 x 3 x 4 m room, front faces inward, open nowhere (its six quads share their edges, so
// together they form a closed surface), moved by `offset`.
void add_box_room(SceneBuilder& b, int walls, int floor, const Vec3& offset = Vec3(0.0f)) {
    const Mat4 id = glm::translate(Mat4(1.0f), offset);
    b.add_instance(b.add_mesh(make_quad({0, 0, 0}, {0, 0, 2}, {2, 0, 0}, floor)), id, -1, "floor");
    b.add_instance(b.add_mesh(make_quad({0, 3, 0}, {2, 0, 0}, {0, 0, 2}, walls)), id, -1,
                   "ceiling");
    b.add_instance(b.add_mesh(make_quad({0, 1.5f, -2}, {2, 0, 0}, {0, 1.5f, 0}, walls)), id, -1,
                   "back");
    b.add_instance(b.add_mesh(make_quad({0, 1.5f, 2}, {0, 1.5f, 0}, {2, 0, 0}, walls)), id, -1,
                   "front");
    b.add_instance(b.add_mesh(make_quad({-2, 1.5f, 0}, {0, 1.5f, 0}, {0, 0, 2}, walls)), id, -1,
                   "left");
    b.add_instance(b.add_mesh(make_quad({2, 1.5f, 0}, {0, 0, 2}, {0, 1.5f, 0}, walls)), id, -1,
                   "right");
}

// 32 x 32 small panels on the ceiling of the room at `offset`: 1024 quads, 2048 emissive
// triangles, of a few colours and strengths spanning 30x, so that choosing lights by power
// matters.
void add_ceiling_panels(SceneBuilder& b, const Vec3& offset) {
    Mesh panels;
    std::vector<int> mats;
    for (int k = 0; k < 8; ++k) {
        const uint32_t h = hash_words({uint32_t(k), 77u});
        const Rgb colour(0.4f + 0.6f * float(h & 0xff) / 255.0f,
                         0.4f + 0.6f * float((h >> 8) & 0xff) / 255.0f,
                         0.4f + 0.6f * float((h >> 16) & 0xff) / 255.0f);
        mats.push_back(b.add_material(make_emitter(
            "panel-" + std::to_string(k), colour * (2.0f + 58.0f * float(k * k) / 49.0f))));
    }
    for (int k = 0; k < 8; ++k) {
        Mesh group;
        for (int i = 0; i < 1024; ++i) {
            if (int(hash_words({uint32_t(i), 3u}) % 8) != k) continue;
            const float x = -1.9f + 3.8f * (float(i % 32) + 0.5f) / 32.0f;
            const float z = -1.9f + 3.8f * (float(i / 32) + 0.5f) / 32.0f;
            append_mesh(group, make_quad({x, 2.998f, z}, {0.02f, 0, 0}, {0, 0, 0.02f}, mats[k]));
        }
        group.material = mats[std::size_t(k)];
        b.add_instance(b.add_mesh(std::move(group)), glm::translate(Mat4(1.0f), offset), -1,
                       "panels");
    }
}

Camera room_camera() {
    Camera cam;
    cam.name = "room-camera";
    cam.yfov_radians = glm::radians(55.0f);
    cam.camera_to_world = look_at_camera({0.0f, 1.4f, 1.8f}, {0.0f, 0.8f, -1.0f}, {0, 1, 0});
    return cam;
}

}  // namespace

SceneModel make_glass_scene() {
    SceneBuilder b("builtin:glass");
    const int walls = b.add_material(make_lambert("walls", Rgb(0.7f)));
    const int floor = b.add_material(make_lambert("floor", Rgb(0.5f, 0.45f, 0.4f)));
    Material glass = make_lambert("clear-glass", Rgb(1.0f));
    glass.transmission_factor = 1.0f;
    glass.roughness_factor = 0.0f;
    glass.ior = 1.5f;
    const int clear = b.add_material(glass);
    glass.name = "blue-glass";
    glass.attenuation_color = Rgb(0.2f, 0.4f, 0.9f);
    glass.attenuation_distance = 0.3f;
    const int blue = b.add_material(glass);
    Material mirror = make_lambert("mirror", Rgb(0.95f));
    mirror.metallic_factor = 1.0f;
    mirror.roughness_factor = 0.0f;
    const int mirror_mat = b.add_material(mirror);
    Material gold = make_lambert("polished-gold", Rgb(1.0f, 0.78f, 0.34f));
    gold.metallic_factor = 1.0f;
    gold.roughness_factor = 0.05f;
    const int gold_mat = b.add_material(gold);
    const int light = b.add_material(make_emitter("light", Rgb(40.0f)));
    add_box_room(b, walls, floor);
    b.add_instance(b.add_mesh(make_quad({0, 2.999f, -0.5f}, {0.25f, 0, 0}, {0, 0, 0.25f}, light)),
                   Mat4(1.0f), -1, "light");
    b.add_instance(b.add_mesh(make_quad({0, 1.5f, -1.99f}, {1.2f, 0, 0}, {0, 1.0f, 0}, mirror_mat)),
                   Mat4(1.0f), -1, "mirror");
    b.add_instance(b.add_mesh(make_sphere(0.4f, 32, 64, clear)),
                   glm::translate(Mat4(1.0f), Vec3(-0.7f, 0.4f, -0.6f)), -1, "clear-sphere");
    b.add_instance(
        b.add_mesh(make_unit_cube(blue)),
        compose_trs({0.6f, 0.3f, -0.3f}, glm::angleAxis(0.5f, Vec3(0, 1, 0)), Vec3(0.6f)), -1,
        "blue-block");
    b.add_instance(b.add_mesh(make_sphere(0.3f, 32, 64, gold_mat)),
                   glm::translate(Mat4(1.0f), Vec3(0.1f, 0.3f, -1.3f)), -1, "gold-sphere");
    b.add_camera(room_camera());
    b.environment().sky = SkyMode::off;
    return b.finish();
}

SceneModel make_many_lights_scene() {
    SceneBuilder b("builtin:many-lights");
    const int walls = b.add_material(make_lambert("walls", Rgb(0.6f)));
    const int floor = b.add_material(make_lambert("floor", Rgb(0.4f)));
    Material plastic = make_lambert("plastic", Rgb(0.2f, 0.5f, 0.3f));
    plastic.roughness_factor = 0.3f;
    const int plastic_mat = b.add_material(plastic);
    add_box_room(b, walls, floor);
    add_ceiling_panels(b, Vec3(0.0f));
    b.add_instance(
        b.add_mesh(make_unit_cube(plastic_mat)),
        compose_trs({-0.5f, 0.4f, -0.8f}, glm::angleAxis(0.4f, Vec3(0, 1, 0)), Vec3(0.8f)), -1,
        "block");
    b.add_instance(b.add_mesh(make_sphere(0.35f, 32, 64, walls)),
                   glm::translate(Mat4(1.0f), Vec3(0.7f, 0.35f, -0.4f)), -1, "ball");
    b.add_camera(room_camera());
    b.environment().sky = SkyMode::off;
    return b.finish();
}

SceneModel make_sealed_lights_scene() {
    SceneBuilder b("builtin:sealed-lights");
    const int walls = b.add_material(make_lambert("walls", Rgb(0.6f)));
    const int floor = b.add_material(make_lambert("floor", Rgb(0.4f)));
    const int lamp = b.add_material(make_emitter("lamp", Rgb(30.0f)));
    add_box_room(b, walls, floor);
    b.add_instance(b.add_mesh(make_quad({0, 2.999f, -0.5f}, {0.3f, 0, 0}, {0, 0, 0.3f}, lamp)),
                   Mat4(1.0f), -1, "lamp");
    b.add_instance(b.add_mesh(make_sphere(0.35f, 32, 64, walls)),
                   glm::translate(Mat4(1.0f), Vec3(0.7f, 0.35f, -0.4f)), -1, "ball");
    // Next door, 1 m away (no wall shared): a closed room full of bright panels.
    const Vec3 next_door(5.0f, 0.0f, 0.0f);
    add_box_room(b, walls, floor, next_door);
    add_ceiling_panels(b, next_door);
    b.add_camera(room_camera());
    b.environment().sky = SkyMode::off;
    return b.finish();
}

}  // namespace pathfarm
