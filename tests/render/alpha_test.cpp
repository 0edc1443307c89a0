// glTF alphaMode and KHR_texture_transform on both backends: MASK cuts out where alpha is below
// alphaCutoff (for camera, bounce and shadow rays alike), BLEND lets through 1 - alpha of the
// rays, OPAQUE ignores alpha, and texture transforms move what a texture shows. A cut-out must
// render as the same surface with the cut-out part removed; the Khronos AlphaBlendModeTest
// shows its green check marks.
#include <filesystem>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_builder.h"
#include "common/scene/load/scene_loader.h"
#include "tests/support/render_helpers.h"
#include "tests/support/test_env.h"

namespace pathfarm::alpha_test {
namespace {

constexpr double kAlpha = 1e-3;

class Alpha : public ::testing::TestWithParam<tracer::BackendKind> {};

Camera look(const Vec3& from, const Vec3& at, float fov_degrees) {
    Camera cam;
    cam.yfov_radians = glm::radians(fov_degrees);
    cam.camera_to_world = glm::inverse(glm::lookAt(from, at, Vec3(0, 1, 0)));
    return cam;
}

// A nearest-filtered texture of w x h texels given as linear-ish RGBA bytes, row 0 on top.
int add_texture(SceneBuilder& b, int w, int h, const std::vector<uint8_t>& rgba) {
    Texture t;
    t.image = b.add_image(Image{"texels", w, h, rgba});
    t.sampler.filter = FilterMode::nearest;
    return b.add_texture(t);
}

// Mean of columns [x0, x1) of an image.
double column_mean(const FloatImage& img, int x0, int x1) {
    double s = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = x0; x < x1; ++x)
            s += img.pixel(x, y).x;
    return s / double(img.height * (x1 - x0));
}

// A black card at z = 0 filling the view, its left half with alpha 0.4 and its right half
// alpha 1, in front of an emitter of radiance 1: what shows through is the card's transparency.
SceneModel card_before_light(const Material& card) {
    SceneBuilder b("card");
    Material m = card;
    m.base_color_texture.texture = add_texture(b, 2, 1, {0, 0, 0, 102, 0, 0, 0, 255});
    const int card_mat = b.add_material(m);
    const int light = b.add_material(make_emitter("light", Rgb(1.0f)));
    b.add_instance(b.add_mesh(make_quad(Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0), card_mat)),
                   Mat4(1.0f));
    b.add_instance(b.add_mesh(make_quad(Vec3(0, 0, -1), Vec3(3, 0, 0), Vec3(0, 3, 0), light)),
                   Mat4(1.0f));
    b.add_camera(look(Vec3(0, 0, 2), Vec3(0.0f), 45.0f));  // sees x in (-0.83, 0.83) at z = 0
    b.environment().sky = SkyMode::off;
    return b.finish();
}

FloatImage render(const SceneModel& scene, tracer::BackendKind backend, int spp = 16) {
    test::RenderRequest r;
    r.width = r.height = 16;
    r.spp = spp;
    r.backend = backend;
    return test::render(scene, r);
}

TEST_P(Alpha, MaskCutsOutBelowTheCutoffAndOpaqueIgnoresAlpha) {
    struct Case {
        AlphaMode mode;
        float cutoff;
        Vec2 uv_offset;
        double left, right;  // expected light seen through each half
    };
    for (const Case& c : {Case{AlphaMode::mask, 0.5f, {0, 0}, 1.0, 0.0},
                          Case{AlphaMode::mask, 0.3f, {0, 0}, 0.0, 0.0},
                          Case{AlphaMode::mask, 0.45f, {0.5f, 0}, 0.0, 1.0},  // halves swapped
                          Case{AlphaMode::opaque, 0.5f, {0, 0}, 0.0, 0.0}}) {
        Material m = make_lambert("card", Rgb(0.0f));
        m.alpha_mode = c.mode;
        m.alpha_cutoff = c.cutoff;
        m.base_color_texture.transform.offset = c.uv_offset;
        const FloatImage img = render(card_before_light(m), GetParam());
        EXPECT_NEAR(column_mean(img, 0, 6), c.left, 1e-3) << "cutoff " << c.cutoff;
        EXPECT_NEAR(column_mean(img, 10, 16), c.right, 1e-3) << "cutoff " << c.cutoff;
    }
}

TEST_P(Alpha, BlendLetsThroughOneMinusAlpha) {
    Material m = make_lambert("card", Rgb(0.0f));
    m.alpha_mode = AlphaMode::blend;
    const FloatImage img = render(card_before_light(m), GetParam(), 256);
    // 16 x 6 pixels x 256 samples: the binomial standard error of each mean is below 0.005.
    EXPECT_NEAR(column_mean(img, 0, 6), 0.6, 0.02) << "alpha 0.4";
    EXPECT_NEAR(column_mean(img, 10, 16), 0.0, 1e-3) << "alpha 1";
}

// A floor lit by a panel through an occluder. With the occluder's left half cut out by MASK,
// every estimator must render what the occluder's right half alone gives.
SceneModel occluded_floor(bool cut_out) {
    SceneBuilder b("occluded-floor");
    const int floor = b.add_material(make_lambert("floor", Rgb(0.7f)));
    const int light = b.add_material(make_emitter("light", Rgb(6.0f)));
    b.add_instance(b.add_mesh(make_quad(Vec3(0.0f), Vec3(2, 0, 0), Vec3(0, 0, -2), floor)),
                   Mat4(1.0f));
    b.add_instance(b.add_mesh(make_quad(Vec3(0, 2, 0), Vec3(0.5f, 0, 0), Vec3(0, 0, 0.5f), light)),
                   Mat4(1.0f));
    Material card = make_lambert("occluder", Rgb(0.5f));
    card.double_sided = true;
    if (cut_out) {
        card.alpha_mode = AlphaMode::mask;
        card.base_color_texture.texture =
            add_texture(b, 2, 1, {255, 255, 255, 0, 255, 255, 255, 255});
        b.add_instance(b.add_mesh(make_quad(Vec3(0, 1, 0), Vec3(0.8f, 0, 0), Vec3(0, 0, -0.8f),
                                            b.add_material(card))),
                       Mat4(1.0f));
    } else {  // only the right half, as geometry
        b.add_instance(b.add_mesh(make_quad(Vec3(0.4f, 1, 0), Vec3(0.4f, 0, 0), Vec3(0, 0, -0.8f),
                                            b.add_material(card))),
                       Mat4(1.0f));
    }
    b.add_camera(look(Vec3(0, 3.0f, 3.0f), Vec3(0, 0.3f, 0), 45.0f));
    b.environment().sky = SkyMode::off;
    return b.finish();
}

std::vector<FloatImage> batches(const SceneModel& scene, LightStrategy strategy, uint32_t seed,
                                tracer::BackendKind backend) {
    test::RenderRequest r;
    r.width = r.height = 24;
    r.spp = 16;
    r.seed = seed;
    r.integrator.strategy = strategy;
    r.integrator.max_depth = 4;
    r.backend = backend;
    return test::render_seeds(scene, r, 16);
}

TEST_P(Alpha, CutOutOccludersCastTheShadowOfWhatRemains) {
    const SceneModel cut = occluded_floor(true), half = occluded_floor(false);
    for (const LightStrategy s : {LightStrategy::light_only, LightStrategy::bsdf_only}) {
        const auto a = batches(cut, s, 10, GetParam()), b = batches(half, s, 40, GetParam());
        const auto r = test::compare_batches(a, b, kAlpha, 4);
        EXPECT_TRUE(r.agree(kAlpha))
            << "strategy " << int(s) << ": min block p " << r.min_pixel_p << " (" << r.worst_a
            << " vs " << r.worst_b << "), mean p " << r.mean_p;
    }
}

// A blended emitter and a blended occluder: next-event estimation weights the emitter by its
// coverage and stochastic shadow rays pass the occluder as often as camera and bounce rays do,
// so light and BSDF sampling agree.
TEST_P(Alpha, BlendedEmittersAndOccludersAgreeAcrossEstimators) {
    SceneBuilder b("blended");
    const int floor = b.add_material(make_lambert("floor", Rgb(0.7f)));
    Material light = make_emitter("light", Rgb(6.0f), true);
    light.alpha_mode = AlphaMode::blend;
    light.base_color_texture.texture =
        add_texture(b, 2, 1, {255, 255, 255, 64, 255, 255, 255, 200});
    Material veil = make_lambert("veil", Rgb(0.5f));
    veil.alpha_mode = AlphaMode::blend;
    veil.base_color_factor.a = 0.5f;
    b.add_instance(b.add_mesh(make_quad(Vec3(0.0f), Vec3(2, 0, 0), Vec3(0, 0, -2), floor)),
                   Mat4(1.0f));
    b.add_instance(b.add_mesh(make_quad(Vec3(0, 2, 0), Vec3(0.6f, 0, 0), Vec3(0, 0, 0.6f),
                                        b.add_material(light))),
                   Mat4(1.0f));
    b.add_instance(b.add_mesh(make_quad(Vec3(0.5f, 1, 0), Vec3(0.5f, 0, 0), Vec3(0, 0, -0.5f),
                                        b.add_material(veil))),
                   Mat4(1.0f));
    b.add_camera(look(Vec3(0, 3.0f, 3.0f), Vec3(0, 0.3f, 0), 45.0f));
    b.environment().sky = SkyMode::off;
    const SceneModel scene = b.finish();
    const auto light_only = batches(scene, LightStrategy::light_only, 70, GetParam());
    const auto bsdf_only = batches(scene, LightStrategy::bsdf_only, 90, GetParam());
    const auto mis = batches(scene, LightStrategy::mis, 110, GetParam());
    for (const auto& [name, other] : {std::pair{"light", &light_only}, std::pair{"mis", &mis}}) {
        const auto r = test::compare_batches(*other, bsdf_only, kAlpha, 4);
        EXPECT_TRUE(r.agree(kAlpha))
            << name << " vs bsdf: min block p " << r.min_pixel_p << " (" << r.worst_a << " vs "
            << r.worst_b << "), mean p " << r.mean_p;
    }
}

// An emissive 2 x 2 texture (red, green / blue, white) seen head-on: the identity shows it as
// it is; an offset of half the width swaps left and right; a quarter turn brings the bottom-
// left texel to the top left (uv' = R uv with R = [cos sin; -sin cos], wrapping).
TEST_P(Alpha, TextureTransformsMoveWhatATextureShows) {
    struct Case {
        UvTransform transform;
        Rgb top_left, top_right;
    };
    const Rgb red(1, 0, 0), green(0, 1, 0), blue(0, 0, 1);
    UvTransform shifted, turned;
    shifted.offset = Vec2(0.5f, 0.0f);
    turned.rotation = 0.5f * kPi;
    for (const Case& c :
         {Case{{}, red, green}, Case{shifted, green, red}, Case{turned, blue, red}}) {
        SceneBuilder b("transformed-texture");
        Material m = make_emitter("screen", Rgb(1.0f));
        m.emissive_texture.texture = add_texture(
            b, 2, 2, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255});
        m.emissive_texture.transform = c.transform;
        // make_quad's uv (0,0) is at c - u - v: v = -y puts uv (0,0) at the top left.
        Mesh screen = make_quad(Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, -1, 0), b.add_material(m));
        std::swap(screen.indices[1], screen.indices[2]);  // face the camera (+z)
        std::swap(screen.indices[4], screen.indices[5]);
        b.add_instance(b.add_mesh(std::move(screen)), Mat4(1.0f));
        b.add_camera(look(Vec3(0, 0, 2), Vec3(0.0f), 45.0f));
        b.environment().sky = SkyMode::off;
        const FloatImage img = render(b.finish(), GetParam(), 4);
        const Vec3 tl = img.pixel(3, 3), tr = img.pixel(12, 3);
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(tl[k], c.top_left[k], 1e-3) << "rotation " << c.transform.rotation;
            EXPECT_NEAR(tr[k], c.top_right[k], 1e-3) << "rotation " << c.transform.rotation;
        }
    }
}

// The Khronos AlphaBlendModeTest (../shared/scenes): beside the OPAQUE and BLEND labels a green
// check mark must show (OPAQUE: a check with alpha 0 that only alpha-ignoring shows; BLEND: a
// transparent red X in front of the check). Before alpha modes, and while OpenImageIO
// premultiplied PNG colour by alpha, both were dark squares.
TEST_P(Alpha, KhronosAlphaBlendModeTestShowsItsCheckMarks) {
    PF_REQUIRE_SCENES(scenes);
    auto scene = load_scene(scenes + "/alpha-blend-mode-test/AlphaBlendModeTest.gltf");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    test::RenderRequest r;
    r.width = 640;  // a check mark is about 25 pixels here (and 0 on the old code)
    r.height = 360;
    r.spp = 8;
    r.backend = GetParam();
    const FloatImage img = test::render(*scene, r);
    // Where the default framing puts the two check marks (0.21 and 0.38 of the width, 0.71 of
    // the height): count clearly green and clearly red pixels around each.
    for (const float x_frac : {0.214f, 0.38f}) {
        int green = 0, red = 0;
        for (int y = int(0.68f * 360); y < int(0.75f * 360); ++y)
            for (int x = int(x_frac * 640) - 16; x < int(x_frac * 640) + 16; ++x) {
                const Vec3 p = img.pixel(x, y);
                green += p.y > 0.1f && p.y > 2.0f * p.x && p.y > 2.0f * p.z;
                red += p.x > 0.1f && p.x > 2.0f * p.y && p.x > 2.0f * p.z;
            }
        EXPECT_GE(green, 12) << "check mark at " << x_frac << " of the width";
        EXPECT_EQ(red, 0) << "red X at " << x_frac << " of the width";
    }
}

// The Khronos TextureCoordinateTest: its README places the image's top-left region (uv 0..0.4)
// on the quad labelled "Top Left" at the top left, which its template colours yellow (and
// top right orange, bottom left blue, bottom right green).
// A v axis read upwards would swap top and bottom.
TEST_P(Alpha, KhronosTextureCoordinateTestKeepsItsCorners) {
    PF_REQUIRE_SCENES(scenes);
    auto scene = load_scene(scenes + "/texture-coordinate-test/TextureCoordinateTest.gltf");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    test::RenderRequest r;
    r.width = r.height = 64;
    r.spp = 8;
    r.backend = GetParam();
    const FloatImage img = test::render(*scene, r);
    const auto corner = [&](int cx, int cy) {
        Vec3 sum(0.0f);
        for (int y = cy - 3; y < cy + 3; ++y)
            for (int x = cx - 3; x < cx + 3; ++x)
                sum += img.pixel(x, y);
        return sum / 36.0f;
    };
    const Vec3 tl = corner(10, 10), tr = corner(54, 10), bl = corner(10, 54), br = corner(54, 54);
    EXPECT_TRUE(tl.x > 0.3f && tl.y > 0.3f && tl.z < 0.1f) << "top left yellow";
    EXPECT_TRUE(tr.x > 0.3f && tr.y < 0.5f * tr.x && tr.z < 0.1f) << "top right orange";
    EXPECT_TRUE(bl.z > 0.3f && bl.x < 0.1f) << "bottom left blue";
    EXPECT_TRUE(br.y > 0.3f && br.x < 0.1f && br.z < 0.1f) << "bottom right green";
}

INSTANTIATE_TEST_SUITE_P(Backends, Alpha, ::testing::ValuesIn(test::built_backends()),
                         test::BackendTestName());

}  // namespace
}  // namespace pathfarm::alpha_test
