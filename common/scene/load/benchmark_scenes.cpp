// Built-in scenes for the benchmarks (bench/time_vs_error.py, bench/skip_bench.py), each made to
// stress one thing: builtin:glass (specular chains: glass, absorbing glass, a mirror, polished
// metal under one small light), builtin:many-lights (a room lit only by 1024 small emissive
// quads of different colours and strengths: light selection) and builtin:sealed-lights (the
// camera's room lit by one lamp, next to a closed room holding those 1024 panels: emitters
// that cannot contribute) and builtin:light-field (9 892 small emitters of six colours facing
// every way over a room's ceiling and upper walls, 2 000 of them on a turning ring: many-light
// sampling, after Brigade's Reflect) and builtin:furnace (a ball inside a sphere of 5 000
// emitting triangles, every surface emitting 0.5 and reflecting half: every pixel is 1 without
// a depth limit; the per-ray cost of a scene where every ray ends on an emitter).
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

SceneModel make_furnace_scene() {
    SceneBuilder b("builtin:furnace");
    Material glow = make_lambert("glow", Rgb(0.5f));
    glow.emissive_factor = Rgb(0.5f);
    const int mat = b.add_material(glow);
    // 51 rings of 50 segments: 5 000 triangles (the poles' rings have one per segment).
    b.add_instance(b.add_mesh(turned_inside_out(make_sphere(4.0f, 51, 50, mat))), Mat4(1.0f), -1,
                   "enclosure");
    b.add_instance(b.add_mesh(make_sphere(1.0f, 24, 48, mat)), Mat4(1.0f), -1, "ball");
    Camera cam;
    cam.yfov_radians = glm::radians(50.0f);
    cam.camera_to_world = look_at_camera({0.0f, 0.0f, 2.5f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0});
    b.add_camera(cam);
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

namespace {

// Small emissive triangles (edge ~`size`) at `centres`, each facing `facing` turned by up to
// `tilt` radians at random, coloured by hash into six materials: one mesh per colour, turning
// about the vertical axis once every 8 s if `spinning`.
void add_emitter_field(SceneBuilder& b, const std::vector<Vec3>& centres,
                       const std::vector<Vec3>& facing, float size, float tilt,
                       const int (&mats)[6], const std::string& name, bool spinning = false) {
    Mesh groups[6];
    for (std::size_t i = 0; i < centres.size(); ++i) {
        const auto h = [&](uint32_t salt) {
            return float(hash_words({uint32_t(i), salt, uint32_t(centres.size())}) & 0xffff) /
                   65535.0f;
        };
        const Vec3 n0 = glm::normalize(facing[i]);
        const Vec3 t =
            glm::normalize(glm::cross(n0, std::abs(n0.y) < 0.9f ? Vec3(0, 1, 0) : Vec3(1, 0, 0)));
        const Vec3 n = glm::normalize(glm::angleAxis(tilt * h(1), t) *
                                      (glm::angleAxis(2.0f * kPi * h(2), n0) * n0));
        const Vec3 u = glm::normalize(glm::cross(n, t)), v = glm::cross(n, u);
        Mesh& m = groups[hash_words({uint32_t(i), 9u}) % 6];
        const auto base = uint32_t(m.positions.size());
        const float a = 2.0f * kPi * h(3);
        for (int k = 0; k < 3; ++k) {  // counter-clockwise seen from n
            const float phi = a + 2.0f * kPi * float(k) / 3.0f;
            m.positions.push_back(centres[i] +
                                  0.6f * size * (std::cos(phi) * u + std::sin(phi) * v));
            m.indices.push_back(base + uint32_t(k));
        }
    }
    for (int c = 0; c < 6; ++c) {
        if (groups[c].positions.empty()) continue;
        groups[c].material = mats[c];
        const int mesh = b.add_mesh(std::move(groups[c]));
        if (spinning)
            b.add_spin(b.add_animatable_instance(mesh, Vec3(0.0f), glm::quat(1, 0, 0, 0), name),
                       Vec3(0, 1, 0), 8.0f, name + "-" + std::to_string(c));
        else
            b.add_instance(mesh, Mat4(1.0f), -1, name);
    }
}

// A grid of emitters on the plane through `corner` spanned by `u` and `v`, facing `n`.
void add_emitter_wall(std::vector<Vec3>& centres, std::vector<Vec3>& facing, const Vec3& corner,
                      const Vec3& u, const Vec3& v, int nu, int nv, const Vec3& n) {
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            centres.push_back(corner + u * ((float(i) + 0.5f) / float(nu)) +
                              v * ((float(j) + 0.5f) / float(nv)));
            facing.push_back(n);
        }
}

// 1 300 two-sided "fireflies" in the air under the ceiling, turned every way.
void add_fireflies(SceneBuilder& b, const int (&two_sided)[6]) {
    std::vector<Vec3> flies, any;
    for (uint32_t i = 0; i < 1300; ++i) {
        const auto h = [&](uint32_t salt) {
            return float(hash_words({i, salt, 4242u}) & 0xffff) / 65535.0f;
        };
        flies.push_back({-1.8f + 3.6f * h(1), 2.0f + 0.8f * h(2), -1.8f + 3.6f * h(3)});
        any.push_back({h(4) - 0.5f, h(5) - 0.5f, h(6) - 0.5f + 1e-3f});
    }
    add_emitter_field(b, flies, any, 0.02f, 0.0f, two_sided, "fireflies");
}

}  // namespace

SceneModel make_light_field_scene() {
    SceneBuilder b("builtin:light-field");
    const int walls = b.add_material(make_lambert("walls", Rgb(0.55f)));
    const int floor = b.add_material(make_lambert("floor", Rgb(0.35f)));
    Material gold = make_lambert("gold", Rgb(1.0f, 0.78f, 0.34f));
    gold.metallic_factor = 1.0f;
    gold.roughness_factor = 0.35f;
    const int gold_mat = b.add_material(gold);
    int mats[6], two_sided[6];
    const Rgb colours[6] = {{1.0f, 0.3f, 0.2f}, {0.2f, 1.0f, 0.3f}, {0.3f, 0.4f, 1.0f},
                            {1.0f, 0.9f, 0.4f}, {0.9f, 0.3f, 1.0f}, {1.0f, 1.0f, 1.0f}};
    for (int c = 0; c < 6; ++c)
        mats[c] = b.add_material(
            make_emitter("led-" + std::to_string(c), colours[c] * (1.0f + 3.0f * float(c))));
    for (int c = 0; c < 6; ++c)
        two_sided[c] =
            b.add_material(make_emitter("firefly-" + std::to_string(c), colours[c] * 4.0f, true));
    add_box_room(b, walls, floor);
    // Ceiling 56 x 56, the upper 1.2 m of three walls 48 x 24: above what the camera sees, as
    // a game's lights mostly are (an emitter in view adds the same pixel-footprint noise to
    // every light sampler, which would hide the difference the benchmark measures).
    std::vector<Vec3> centres, facing;
    add_emitter_wall(centres, facing, {-1.9f, 2.97f, -1.9f}, {3.8f, 0, 0}, {0, 0, 3.8f}, 56, 56,
                     {0, -1, 0});
    add_emitter_wall(centres, facing, {-1.9f, 1.7f, -1.97f}, {3.8f, 0, 0}, {0, 1.2f, 0}, 48, 24,
                     {0, 0, 1});
    add_emitter_wall(centres, facing, {-1.97f, 1.7f, -1.9f}, {0, 0, 3.8f}, {0, 1.2f, 0}, 48, 24,
                     {1, 0, 0});
    add_emitter_wall(centres, facing, {1.97f, 1.7f, -1.9f}, {0, 0, 3.8f}, {0, 1.2f, 0}, 48, 24,
                     {-1, 0, 0});
    add_emitter_field(b, centres, facing, 0.03f, 0.6f, mats, "led-walls");
    // 2 000 on a turning ring, facing out and down; 1 300 two-sided "fireflies" in the air.
    std::vector<Vec3> ring, out;
    for (int i = 0; i < 2000; ++i) {
        const float a = 2.0f * kPi * float(i) / 2000.0f;
        const float y = 2.2f + 0.15f * float(i % 5);
        ring.push_back({0.8f * std::cos(a), y, 0.8f * std::sin(a)});
        out.push_back({std::cos(a), -0.5f, std::sin(a)});
    }
    add_emitter_field(b, ring, out, 0.03f, 0.3f, mats, "ring", true);
    add_fireflies(b, two_sided);
    b.add_instance(
        b.add_mesh(make_unit_cube(walls)),
        compose_trs({-0.6f, 0.45f, -0.7f}, glm::angleAxis(0.5f, Vec3(0, 1, 0)), Vec3(0.9f)), -1,
        "block");
    b.add_instance(b.add_mesh(make_sphere(0.4f, 32, 64, gold_mat)),
                   glm::translate(Mat4(1.0f), Vec3(0.7f, 0.4f, -0.5f)), -1, "gold-ball");
    Camera camera = room_camera();  // looking down at the floor, the block and the ball
    camera.camera_to_world = look_at_camera({0.0f, 1.3f, 1.9f}, {0.0f, 0.1f, -1.0f}, {0, 1, 0});
    b.add_camera(camera);
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
