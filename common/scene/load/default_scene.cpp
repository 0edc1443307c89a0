// builtin:default, the demo room: a sunlit room with a procedurally textured floor,
// instanced pillars, crates and spheres, a mirror, an absorbing glass sphere, two ceiling
// lights of different sizes and a small bright lamp.
#include <glm/gtc/matrix_transform.hpp>

#include "common/base/hash.h"
#include "common/math/transform.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_builder.h"

namespace pathfarm {
namespace {

// Tiles with grout and a slight per-tile tint: a game-like floor texture, made in code so the
// demo needs no files.
Image make_floor_image(int size) {
    Image img{"procedural-floor-tiles", size, size,
              std::vector<uint8_t>(std::size_t(size) * size * 4)};
    const int tile = size / 4;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const int tx = x / tile, ty = y / tile;
            const bool grout = x % tile < 2 || y % tile < 2;
            const bool dark = (tx + ty) % 2 == 1;
            const uint32_t h = hash_words({uint32_t(tx), uint32_t(ty)});
            const float tint = 0.9f + 0.2f * float(h & 0xff) / 255.0f;
            Vec3 c = grout ? Vec3(0.25f)
                           : (dark ? Vec3(0.35f, 0.3f, 0.27f) : Vec3(0.8f, 0.76f, 0.7f)) * tint;
            uint8_t* p = &img.rgba[(std::size_t(y) * size + x) * 4];
            for (int k = 0; k < 3; ++k)
                p[k] = uint8_t(std::lround(255.0f * linear_to_srgb(std::clamp(c[k], 0.0f, 1.0f))));
            p[3] = 255;
        }
    return img;
}

Material make_material(std::string name, Rgb base, float metallic, float roughness) {
    Material m;
    m.name = std::move(name);
    m.base_color_factor = Vec4(base, 1.0f);
    m.metallic_factor = metallic;
    m.roughness_factor = roughness;
    return m;
}

Mat4 at(Vec3 t, float yaw_deg = 0.0f, Vec3 s = Vec3(1.0f)) {
    return compose_trs(t, glm::angleAxis(glm::radians(yaw_deg), Vec3(0, 1, 0)), s);
}

void add_room(SceneBuilder& b, int wall, int floor) {
    const Mat4 id(1.0f);
    // Room: x in [-4, 4], y in [0, 3], z in [-8, 1]. Front faces point inwards.
    Mesh floor_mesh = make_quad({0, 0, -3.5f}, {0, 0, 4.5f}, {4, 0, 0}, floor);
    for (Vec2& uv : floor_mesh.uvs)
        uv *= Vec2(4.5f, 4.0f);
    b.add_instance(b.add_mesh(std::move(floor_mesh)), id, -1, "floor");
    b.add_instance(b.add_mesh(make_quad({0, 3, -3.5f}, {4, 0, 0}, {0, 0, 4.5f}, wall)), id, -1,
                   "ceiling");
    b.add_instance(b.add_mesh(make_quad({0, 1.5f, -8}, {4, 0, 0}, {0, 1.5f, 0}, wall)), id, -1,
                   "back-wall");
    b.add_instance(b.add_mesh(make_quad({0, 1.5f, 1}, {0, 1.5f, 0}, {4, 0, 0}, wall)), id, -1,
                   "front-wall");
    b.add_instance(b.add_mesh(make_quad({-4, 1.5f, -3.5f}, {0, 1.5f, 0}, {0, 0, 4.5f}, wall)), id,
                   -1, "left-wall");
    // The right wall (x = 4) has a window: z in [-5.5, -2.5], y in [0.8, 2.4].
    Mesh right = make_quad({4, 0.4f, -3.5f}, {0, 0, 4.5f}, {0, 0.4f, 0}, wall);
    append_mesh(right, make_quad({4, 2.7f, -3.5f}, {0, 0, 4.5f}, {0, 0.3f, 0}, wall));
    append_mesh(right, make_quad({4, 1.6f, -6.75f}, {0, 0, 1.25f}, {0, 0.8f, 0}, wall));
    append_mesh(right, make_quad({4, 1.6f, -0.75f}, {0, 0, 1.75f}, {0, 0.8f, 0}, wall));
    b.add_instance(b.add_mesh(std::move(right)), id, -1, "right-wall-with-window");
}

}  // namespace

Mat4 default_scene_door_transform(float open_radians) {
    const Mat4 hinge = glm::translate(Mat4(1.0f), Vec3(0.9f, 0.0f, -7.94f));
    const Mat4 swing = glm::rotate(Mat4(1.0f), open_radians, Vec3(0, 1, 0));
    const Mat4 panel = glm::translate(Mat4(1.0f), Vec3(0.45f, 1.0f, 0.03f));
    return hinge * swing * panel * glm::scale(Mat4(1.0f), Vec3(0.9f, 2.0f, 0.06f));
}

namespace {

struct DefaultMaterials {
    int floor, wall, marble, crate, gold, mirror, glass, wood, big_light, small_light, lamp;
};

DefaultMaterials add_default_materials(SceneBuilder& b) {
    DefaultMaterials m{};
    const int floor_image = b.add_image(make_floor_image(256));
    Material floor_mat = make_material("floor-tiles", Rgb(1.0f), 0.0f, 0.6f);
    floor_mat.base_color_texture.texture = b.add_texture(Texture{floor_image, Sampler{}});
    m.floor = b.add_material(floor_mat);
    m.wall = b.add_material(make_lambert("plaster", Rgb(0.7f, 0.68f, 0.64f)));
    m.marble = b.add_material(make_material("marble", Rgb(0.85f, 0.85f, 0.82f), 0.0f, 0.25f));
    m.crate = b.add_material(make_material("painted-crate", Rgb(0.55f, 0.18f, 0.08f), 0.0f, 0.5f));
    m.gold = b.add_material(make_material("gold", Rgb(1.0f, 0.78f, 0.34f), 1.0f, 0.3f));
    m.mirror = b.add_material(make_material("mirror", Rgb(0.95f), 1.0f, 0.0f));
    Material glass = make_material("green-glass", Rgb(1.0f), 0.0f, 0.0f);
    glass.transmission_factor = 1.0f;
    glass.ior = 1.5f;
    glass.attenuation_color = Rgb(0.3f, 0.8f, 0.5f);
    glass.attenuation_distance = 0.5f;
    m.glass = b.add_material(glass);
    m.wood = b.add_material(make_material("door-wood", Rgb(0.32f, 0.2f, 0.11f), 0.0f, 0.55f));
    m.big_light = b.add_material(make_emitter("ceiling-panel", Rgb(2.5f)));
    m.small_light = b.add_material(make_emitter("spot-panel", Rgb(18.0f, 16.0f, 13.0f)));
    m.lamp = b.add_material(make_emitter("lamp-bulb", Rgb(400.0f, 300.0f, 180.0f)));
    return m;
}

// The ceiling panels, the lamp bulb and the wall mirror.
void add_lights_and_mirror(SceneBuilder& b, const DefaultMaterials& m) {
    const Mat4 id(1.0f);
    b.add_instance(
        b.add_mesh(make_quad({-1.5f, 2.999f, -4}, {0.75f, 0, 0}, {0, 0, 0.75f}, m.big_light)), id,
        -1, "big-light");
    b.add_instance(
        b.add_mesh(make_quad({1.8f, 2.999f, -6.5f}, {0.2f, 0, 0}, {0, 0, 0.2f}, m.small_light)), id,
        -1, "small-light");
    b.add_instance(b.add_mesh(make_sphere(0.04f, 8, 16, m.lamp)), at({-3.0f, 1.05f, -6.8f}), -1,
                   "lamp");
    b.add_instance(
        b.add_mesh(make_quad({-3.98f, 1.5f, -3.0f}, {0, 0.9f, 0}, {0, 0, 1.2f}, m.mirror)), id, -1,
        "mirror");
}

// Pillars, crates, balls and the door.
void add_furniture(SceneBuilder& b, const DefaultMaterials& m) {
    const int pillar = b.add_mesh(make_cylinder(0.25f, 3.0f, 32, m.marble));
    for (Vec3 p : {Vec3(-2.5f, 0, -2), Vec3(2.5f, 0, -2), Vec3(-2.5f, 0, -6), Vec3(2.5f, 0, -6)})
        b.add_instance(pillar, at(p), -1, "pillar");
    const int cube = b.add_mesh(make_unit_cube(m.crate));
    b.add_instance(cube, at({-1.2f, 0.3f, -5.0f}, 20.0f, Vec3(0.6f)), -1, "crate");
    b.add_instance(cube, at({-0.9f, 0.8f, -5.1f}, 35.0f, Vec3(0.4f)), -1, "crate");
    b.add_instance(cube, at({1.6f, 0.25f, -3.2f}, -15.0f, Vec3(0.5f)), -1, "crate");
    b.add_instance(cube, at({-3.0f, 0.5f, -6.8f}, 0.0f, Vec3(0.5f, 1.0f, 0.5f)), -1, "lamp-stand");
    const int ball = b.add_mesh(make_sphere(0.35f, 32, 64, m.gold));
    b.add_instance(ball, at({0.6f, 0.35f, -4.2f}), -1, "gold-ball");
    b.add_instance(ball, at({2.6f, 0.35f, -4.6f}), -1, "gold-ball");
    // A door in front of the back wall, hinged at x = 0.9: the game (coordinator/game) swings
    // it open when the player aims at it and presses the action key.
    b.add_instance(b.add_mesh(make_unit_cube(m.wood)), default_scene_door_transform(0.0f), -1,
                   "door");
    b.add_instance(b.add_mesh(make_sphere(0.45f, 32, 64, m.glass)), at({-0.4f, 0.45f, -2.8f}), -1,
                   "glass-ball");
}

}  // namespace

SceneModel make_default_scene() {
    SceneBuilder b("builtin:default");
    const DefaultMaterials m = add_default_materials(b);
    add_room(b, m.wall, m.floor);
    add_lights_and_mirror(b, m);
    add_furniture(b, m);
    Camera cam;
    cam.name = "default-camera";
    cam.yfov_radians = glm::radians(60.0f);
    cam.camera_to_world = look_at_camera({0.3f, 1.7f, 0.4f}, {0.0f, 0.8f, -5.0f}, {0, 1, 0});
    b.add_camera(cam);
    b.environment().sky = SkyMode::on;  // the window lets the sun into a lit room
    b.environment().sun_direction = glm::normalize(Vec3(1.0f, 0.75f, 0.1f));
    return b.finish();
}

std::vector<std::string> builtin_scene_names() {
    return {"cornell",     "default",       "glass",  "many-lights",
            "light-field", "sealed-lights", "furnace"};
}

Result<SceneModel> make_builtin_scene(const std::string& name) {
    if (name == "cornell") return make_cornell_box();
    if (name == "default") return make_default_scene();
    if (name == "glass") return make_glass_scene();
    if (name == "many-lights") return make_many_lights_scene();
    if (name == "light-field") return make_light_field_scene();
    if (name == "sealed-lights") return make_sealed_lights_scene();
    if (name == "furnace") return make_furnace_scene();
    return make_error(ErrorCode::not_found,
                      "builtin:{}: no such built-in scene (known: cornell, default, glass, "
                      "many-lights, light-field, sealed-lights, furnace)",
                      name);
}

}  // namespace pathfarm
