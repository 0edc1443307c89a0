// The Cornell box after the measured data of the Cornell Program of Computer Graphics,
// axis-aligned walls, the two blocks as instances of one unit cube.
#include <glm/gtc/matrix_transform.hpp>

#include "common/math/transform.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_builder.h"

namespace pathfarm {

SceneModel make_cornell_box() {
    SceneBuilder b("builtin:cornell");
    const int white = b.add_material(make_lambert("white", Rgb(0.725f, 0.71f, 0.68f)));
    const int red = b.add_material(make_lambert("red", Rgb(0.63f, 0.065f, 0.05f)));
    const int green = b.add_material(make_lambert("green", Rgb(0.14f, 0.45f, 0.091f)));
    const int light = b.add_material(make_emitter("light", Rgb(17.0f, 12.0f, 4.0f)));

    const float w = 0.5528f, h = 0.5488f, d = 0.5592f;
    const Vec3 x(0.5f * w, 0, 0), y(0, 0.5f * h, 0), z(0, 0, 0.5f * d);
    const Vec3 c(0.5f * w, 0.5f * h, 0.5f * d);
    const Mat4 id(1.0f);
    // Front faces point into the room.
    b.add_instance(b.add_mesh(make_quad(c - y, z, x, white)), id, -1, "floor");
    b.add_instance(b.add_mesh(make_quad(c + y, x, z, white)), id, -1, "ceiling");
    b.add_instance(b.add_mesh(make_quad(c + z, y, x, white)), id, -1, "back");
    b.add_instance(b.add_mesh(make_quad(c + x, z, y, red)), id, -1, "left-red");
    b.add_instance(b.add_mesh(make_quad(c - x, y, z, green)), id, -1, "right-green");
    const Vec3 lc(0.278f, h - 0.0005f, 0.2795f);
    b.add_instance(b.add_mesh(make_quad(lc, Vec3(0.065f, 0, 0), Vec3(0, 0, 0.0525f), light)), id,
                   -1, "light");

    const int cube = b.add_mesh(make_unit_cube(white));
    const auto block = [&](Vec3 centre, float angle_deg, Vec3 size) {
        return compose_trs(centre, glm::angleAxis(glm::radians(angle_deg), Vec3(0, 1, 0)), size);
    };
    b.add_instance(cube, block({0.1855f, 0.0825f, 0.169f}, -17.0f, {0.167f, 0.165f, 0.167f}), -1,
                   "short-block");
    b.add_instance(cube, block({0.3685f, 0.165f, 0.3513f}, 17.0f, {0.166f, 0.33f, 0.166f}), -1,
                   "tall-block");

    Camera cam;
    cam.name = "cornell-camera";
    cam.yfov_radians = 2.0f * std::atan(0.0125f / 0.035f);
    cam.camera_to_world =
        look_at_camera({0.278f, 0.273f, -0.8f}, {0.278f, 0.273f, 0.0f}, {0, 1, 0});
    b.add_camera(cam);
    b.environment().sky = SkyMode::off;
    return b.finish();
}

}  // namespace pathfarm
