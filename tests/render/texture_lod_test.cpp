// Texture level of detail on both backends: a white wall lit mostly by light bouncing off a
// floor of one-texel black and white checks. Past the camera's hit the paths read the floor
// at coarse mip levels, whose texels must hold the checks' average light (0.5, not the 0.216
// of averaging sRGB codes) at the level the footprint asks for, so the wall's converged image
// with --texture-lod on agrees with the one that reads every texel (Welch tests over batches,
// Šidák-corrected, as estimator_agreement_test). The same comparison must fail when the
// chain's averages are wrong: a floor whose coarse levels are darkened (what sRGB-code
// averaging gives) is told apart.
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "tests/support/render_helpers.h"

namespace pathfarm::texture_lod_test {
namespace {

constexpr double kAlpha = 1e-3;

class TextureLod : public ::testing::TestWithParam<tracer::BackendKind> {};

int add_quad(SceneModel& scene, const Vec3 corners[4], int material) {
    Mesh mesh;
    mesh.positions.assign(corners, corners + 4);
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.material = material;
    scene.meshes.push_back(mesh);
    scene.instances.push_back({int(scene.meshes.size()) - 1, -1, Mat4(1.0f), 0, false});
    return int(scene.meshes.size()) - 1;
}

Material lambert(Rgb colour) {
    Material m;
    m.base_color_factor = Vec4(colour, 1.0f);
    m.metallic_factor = 0.0f;
    m.specular_factor = 0.0f;
    m.double_sided = true;
    return m;
}

// `dark`: the checks' byte values are what the test uses as the floor (255/0 normally).
SceneModel bounce_room(uint8_t bright, uint8_t dark) {
    SceneModel scene;
    scene.name = "texture-lod-room";
    constexpr int kSize = 256;
    Image checks{"checks", kSize, kSize, {}};
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const uint8_t v = (x + y) % 2 ? bright : dark;
            checks.rgba.insert(checks.rgba.end(), {v, v, v, 255});
        }
    scene.images.push_back(std::move(checks));
    Texture t;
    t.image = 0;
    t.sampler.filter = FilterMode::nearest;
    scene.textures.push_back(t);
    Material floor = lambert(Rgb(1.0f));
    floor.base_color_texture.texture = 0;
    scene.materials = {floor, lambert(Rgb(0.8f)), lambert(Rgb(0.0f))};
    scene.materials[2].emissive_factor = Rgb(20.0f);
    const Vec3 floor_quad[4] = {{-2, 0, -1}, {2, 0, -1}, {2, 0, 3}, {-2, 0, 3}};
    const Vec3 wall[4] = {{-2, 0, -1}, {2, 0, -1}, {2, 2, -1}, {-2, 2, -1}};
    // Low over the floor, far from the wall: the wall sees it at grazing angles only.
    const Vec3 light[4] = {
        {-0.3f, 0.4f, 1.6f}, {0.3f, 0.4f, 1.6f}, {0.3f, 0.4f, 2.2f}, {-0.3f, 0.4f, 2.2f}};
    add_quad(scene, floor_quad, 0);
    add_quad(scene, wall, 1);
    add_quad(scene, light, 2);
    Camera cam;
    cam.yfov_radians = glm::radians(30.0f);
    cam.camera_to_world =
        glm::inverse(glm::lookAt(Vec3(0, 1.2f, 1.0f), Vec3(0, 1.2f, -1), Vec3(0, 1, 0)));
    scene.cameras.push_back(cam);
    return scene;
}

std::vector<FloatImage> batches(const SceneModel& scene, tracer::BackendKind backend, bool lod,
                                uint32_t seed) {
    test::RenderRequest r;
    r.width = 16;
    r.height = 12;
    r.spp = 32;
    r.seed = seed;
    r.backend = backend;
    r.texture_lod = lod;
    r.integrator.max_depth = 4;
    return test::render_seeds(scene, r, 16);
}

TEST_P(TextureLod, CoarseLevelsKeepTheLightTheFloorReflects) {
    const SceneModel scene = bounce_room(255, 0);
    const auto lod = batches(scene, GetParam(), true, 100);
    const auto flat = batches(scene, GetParam(), false, 300);
    const auto r = test::compare_batches(lod, flat, kAlpha, 2);
    EXPECT_TRUE(r.agree(kAlpha)) << "min pixel p " << r.min_pixel_p << " (threshold "
                                 << r.pixel_threshold << "), mean p " << r.mean_p << "; worst "
                                 << r.worst_a << " (lod) vs " << r.worst_b << " (level 0)";
    // What averaging sRGB codes would give the coarse levels: checks of 0 and 255 become a
    // uniform code 128 (0.216 of the light instead of 0.5). Rendered with level 0 everywhere,
    // that floor must be told apart from the true one, or the comparison above could not fail.
    const auto darkened = batches(bounce_room(128, 128), GetParam(), false, 500);
    const auto d = test::compare_batches(lod, darkened, kAlpha, 2);
    EXPECT_FALSE(d.agree(kAlpha)) << "a floor of half the light passed as the same";
}

INSTANTIATE_TEST_SUITE_P(Backends, TextureLod, ::testing::ValuesIn(test::built_backends()),
                         test::BackendTestName());

}  // namespace
}  // namespace pathfarm::texture_lod_test
