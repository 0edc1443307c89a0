// Numerical-stability stress tests (the fast part): the same scene at 1e-3 and 1e3 scale and
// 1e4 m away renders the same image, degenerate geometry is repaired with a
// warning and renders finite pixels, textures with NaN texels and a tiny very bright light give
// finite pixels, 10^5
// samples per pixel accumulate without drift, and seeded random scenes render finite images
// whose energy is bounded by their emitters and albedos.
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/film/image_io.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_builder.h"
#include "common/scene/load/scene_loader.h"
#include "common/scene/load/validate.h"
#include "tests/support/render_helpers.h"
#include "tests/support/test_env.h"

namespace pathfarm::stress_test {
namespace {

// The scene with every instance and the camera moved by `m` (a similarity transform).
SceneModel transformed(SceneModel s, const Mat4& m) {
    for (Instance& i : s.instances)
        i.transform = m * i.transform;
    for (Camera& c : s.cameras)
        c.camera_to_world = m * c.camera_to_world;
    return s;
}

std::vector<FloatImage> batches(const SceneModel& scene, int n, int spp, int size) {
    std::vector<FloatImage> out;
    for (int k = 0; k < n; ++k) {
        test::RenderRequest r;
        r.width = r.height = size;
        r.spp = spp;
        r.seed = 1000 + uint32_t(k);
        out.push_back(test::render(scene, r));
    }
    return out;
}

std::size_t nonfinite(const FloatImage& img) { return count_nonfinite(img); }

// Every pixel finite, and light arrives somewhere (what `what` names is visible and lit).
void expect_finite_and_lit(const FloatImage& img, const char* what) {
    EXPECT_EQ(nonfinite(img), 0u);
    double sum = 0.0;
    for (float v : img.rgb)
        sum += v;
    EXPECT_GT(sum, 0.0) << what;
}

class ScaleInvariance : public ::testing::TestWithParam<float> {};

TEST_P(ScaleInvariance, CornellRendersTheSameImage) {
    const float scale = GetParam();
    const SceneModel base = make_cornell_box();
    const SceneModel scaled = transformed(base, glm::scale(Mat4(1.0f), Vec3(scale)));
    const auto a = batches(base, 8, 16, 16);
    const auto b = batches(scaled, 8, 16, 16);
    const test::AgreementResult r = test::compare_batches(a, b, 1e-3);
    EXPECT_TRUE(r.agree(1e-3)) << "scale " << scale << ": min pixel p " << r.min_pixel_p
                               << " (threshold " << r.pixel_threshold << "), mean p " << r.mean_p;
    for (const FloatImage& img : b)
        EXPECT_EQ(nonfinite(img), 0u);
}

INSTANTIATE_TEST_SUITE_P(TinyAndHuge, ScaleInvariance, ::testing::Values(1e-3f, 1e3f));

// 1e4 m from the origin a float step is 1 mm: without camera-relative rendering
// (recentre_on_camera) this scene lost 15 % of its light to leaks and acne (measured).
TEST(LargeCoordinates, CornellTranslatedFarAwayRendersTheSameImage) {
    const SceneModel base = make_cornell_box();
    const SceneModel far = transformed(base, glm::translate(Mat4(1.0f), Vec3(1e4f, -1e4f, 1e4f)));
    const auto a = batches(base, 8, 16, 16);
    const auto b = batches(far, 8, 16, 16);
    const test::AgreementResult r = test::compare_batches(a, b, 1e-3);
    EXPECT_TRUE(r.agree(1e-3)) << "min pixel p " << r.min_pixel_p << " (threshold "
                               << r.pixel_threshold << "), mean p " << r.mean_p;
}

TEST(Degenerate, RepairedWithAWarningAndRendersFinitePixels) {
    SceneBuilder b("degenerate");
    const int white = b.add_material(make_lambert("white", Rgb(0.7f)));
    const int light = b.add_material(make_emitter("light", Rgb(5.0f)));
    b.add_instance(b.add_mesh(make_quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, white)), Mat4(1.0f));
    b.add_instance(b.add_mesh(make_quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, white)),
                   Mat4(1.0f));  // coincident with the first
    b.add_instance(b.add_mesh(make_quad({0, 0, 2}, {0.5f, 0, 0}, {0, -0.5f, 0}, light)),
                   Mat4(1.0f));
    Mesh bad;
    bad.material = white;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    bad.positions = {{0, 0, 0.5f},
                     {0.2f, 0, 0.5f},
                     {0.4f, 0, 0.5f},  // collinear: zero area
                     {nan, 0, 0.5f},
                     {0, 0.3f, 0.5f},
                     {0.3f, 0.3f, 0.5f},  // a NaN vertex
                     {inf, 0, 0.5f},
                     {0, -inf, 0.5f},
                     {0.1f, 0.1f, 0.5f},  // Inf vertices
                     {0.1f, 0.1f, 0.5f},
                     {0.1f, 0.1f, 0.5f},
                     {0.1f, 0.1f, 0.5f},  // one point
                     {-1e7f, -1e7f, -3},
                     {1e7f, -1e7f, -3},
                     {0, 1e7f, -3},  // huge
                     {0.5f, 0.5f, 0.6f},
                     {0.5f + 1e-7f, 0.5f, 0.6f},
                     {0.5f, 0.5f + 1e-7f, 0.6f}};
    bad.normals.assign(bad.positions.size(), Vec3(0.0f));  // zero-length normals
    for (uint32_t i = 0; i < bad.positions.size(); ++i)
        bad.indices.push_back(i);
    b.add_instance(b.add_mesh(std::move(bad)), Mat4(1.0f));
    Camera cam;
    cam.camera_to_world =
        glm::inverse(glm::lookAt(Vec3(0.5f, 0.5f, 3), Vec3(0.5f, 0.5f, 0), Vec3(0, 1, 0)));
    b.add_camera(cam);
    b.environment().sky = SkyMode::off;
    SceneModel scene = b.finish();
    RepairReport report;
    ASSERT_TRUE(validate_and_repair(scene, "stress", &report).ok());
    EXPECT_EQ(report.dropped_nonfinite, 2u);
    EXPECT_GE(report.dropped_degenerate, 2u);  // the collinear and the one-point triangles
    test::RenderRequest r;
    r.width = r.height = 24;
    r.spp = 16;
    const FloatImage img = test::render(scene, r);
    expect_finite_and_lit(img, "the lit quad is visible");
}

TEST(HardTransport, TexturesWithNanTexelsGiveFinitePixels) {
    // A float (EXR) base-colour texture full of NaN and infinities on a lit quad, loaded from
    // an OBJ as a user's file would be: the texels get defined values, the pixels stay finite.
    const std::string dir = test::scratch_dir();
    FloatImage tex(8, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            tex.set_pixel(x, y,
                          (x + y) % 3 == 0   ? Rgb(std::nanf(""))
                          : (x + y) % 3 == 1 ? Rgb(INFINITY, -INFINITY, 0.5f)
                                             : Rgb(0.8f));
    ASSERT_TRUE(write_image(dir + "/nan_texels.exr", tex).ok());
    std::ofstream(dir + "/nan.mtl") << "newmtl textured\nKd 1 1 1\nmap_Kd nan_texels.exr\n"
                                    << "newmtl lamp\nKd 0 0 0\nKe 5 5 5\n";
    std::ofstream(dir + "/nan.obj") << "mtllib nan.mtl\n"
                                       "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                       "v -0.3 -0.3 2\nv -0.3 0.3 2\nv 0.3 0.3 2\nv 0.3 -0.3 2\n"
                                       "usemtl textured\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n"
                                       "usemtl lamp\nf 5 6 7\nf 5 7 8\n";
    auto scene = load_scene(dir + "/nan.obj");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    ASSERT_EQ(scene->images.size(), 1u);
    test::RenderRequest r;
    r.width = r.height = 16;
    r.spp = 8;
    const FloatImage img = test::render(*scene, r);
    expect_finite_and_lit(img, "the textured quad is lit");
}

TEST(HardTransport, TinyVeryBrightLightGivesFinitePixels) {
    SceneBuilder b("tiny-light");
    const int white = b.add_material(make_lambert("white", Rgb(0.8f)));
    const int mirror_mat = [&] {
        Material m = make_lambert("mirror", Rgb(0.95f));
        m.metallic_factor = 1.0f;
        m.roughness_factor = 0.0f;
        return b.add_material(m);
    }();
    const int lamp = b.add_material(make_emitter("lamp", Rgb(1e6f)));
    b.add_instance(b.add_mesh(make_quad({0, 0, 0}, {2, 0, 0}, {0, 0, 2}, white)), Mat4(1.0f));
    b.add_instance(b.add_mesh(make_quad({0, 1, -1}, {2, 0, 0}, {0, 1, 0}, mirror_mat)), Mat4(1.0f));
    b.add_instance(b.add_mesh(make_sphere(1e-3f, 8, 16, lamp)),
                   glm::translate(Mat4(1.0f), Vec3(0, 0.5f, 0)));
    Camera cam;
    cam.camera_to_world =
        glm::inverse(glm::lookAt(Vec3(0, 1.0f, 3), Vec3(0, 0.3f, 0), Vec3(0, 1, 0)));
    b.add_camera(cam);
    b.environment().sky = SkyMode::off;
    test::RenderRequest r;
    r.width = r.height = 24;
    r.spp = 32;
    r.integrator.max_depth = 16;  // mirror chains to the depth limit
    const FloatImage img = test::render(b.finish(), r);
    EXPECT_EQ(nonfinite(img), 0u);
}

TEST(LongAccumulation, HundredThousandSamplesMatchTheFurnaceValue) {
    // Every pixel converges to E / (1 - a) = 1.0; 1e5 samples of a 2x2 image, accumulated in
    // double. Per-sample deviation here is ~0.21 (measured), so a pixel's standard error is
    // ~7e-4; 4e-3 is about 6 of them: drift or bias beyond that fails.
    test::RenderRequest r;
    r.width = r.height = 2;
    r.spp = 100000;
    r.integrator.max_depth = 64;  // 2^-64 truncation: the analytic value holds
    const FloatImage img = test::render(test::make_furnace(0.5f, 0.5f), r);
    for (float v : img.rgb)
        EXPECT_NEAR(v, 1.0, 4e-3);
}

// A few dozen cases here; bench/stress.sh runs 1000+ under ASan/UBSan
// (PATHFARM_STRESS_CASES).
int fuzz_cases() {
    const char* n = std::getenv("PATHFARM_STRESS_CASES");
    return n ? std::max(1, std::atoi(n)) : 24;
}

TEST(Fuzz, RandomScenesRenderFiniteBoundedImages) {
    std::mt19937 rng(20261122);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const int cases = fuzz_cases();
    for (int c = 0; c < cases; ++c) {
        SceneBuilder b("fuzz-" + std::to_string(c));
        float max_emission = 0.0f, max_albedo = 0.0f;
        std::vector<int> mats;
        for (int m = 0; m < 4; ++m) {
            Material mat = make_lambert("m", Rgb(u(rng), u(rng), u(rng)) * 0.9f);
            mat.metallic_factor = u(rng) < 0.3f ? 1.0f : 0.0f;
            mat.roughness_factor = u(rng);
            if (u(rng) < 0.2f) {
                mat.transmission_factor = 1.0f;
                mat.ior = 1.0f + u(rng);
            }
            if (u(rng) < 0.4f) mat.emissive_factor = Rgb(u(rng), u(rng), u(rng)) * 10.0f;
            max_emission = std::max(max_emission, max_component(mat.emissive_factor));
            max_albedo = std::max(max_albedo, max_component(Rgb(mat.base_color_factor)));
            mats.push_back(b.add_material(mat));
        }
        if (max_emission == 0.0f) {
            mats[0] = b.add_material(make_emitter("light", Rgb(5.0f)));
            max_emission = 5.0f;
        }
        for (int o = 0; o < 6; ++o) {
            const int mat = mats[std::size_t(rng() % mats.size())];
            const Vec3 p(u(rng) * 4 - 2, u(rng) * 4 - 2, u(rng) * 4 - 2);
            const float s = std::exp(u(rng) * 6.0f - 4.0f);  // 0.02 .. 7
            Mesh mesh = o % 3 == 0   ? make_sphere(1.0f, 8, 16, mat)
                        : o % 3 == 1 ? make_unit_cube(mat)
                                     : make_quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, mat);
            b.add_instance(b.add_mesh(std::move(mesh)),
                           glm::translate(Mat4(1.0f), p) *
                               glm::rotate(Mat4(1.0f), u(rng) * 6.28f,
                                           glm::normalize(Vec3(u(rng) + 0.1f, u(rng), u(rng)))) *
                               glm::scale(Mat4(1.0f), Vec3(s)));
        }
        Camera cam;
        cam.yfov_radians = 0.2f + 2.5f * u(rng);
        cam.camera_to_world =
            glm::inverse(glm::lookAt(Vec3(u(rng) * 8 - 4, u(rng) * 8 - 4, 6 + u(rng) * 4),
                                     Vec3(u(rng) - 0.5f, u(rng) - 0.5f, 0), Vec3(0, 1, 0)));
        b.add_camera(cam);
        b.environment().sky = SkyMode::off;
        SceneModel scene = b.finish();
        ASSERT_TRUE(validate_and_repair(scene, "fuzz").ok());
        test::RenderRequest r;
        r.width = r.height = 12;
        r.spp = 16;
        r.seed = uint32_t(c);
        const FloatImage img = test::render(scene, r);
        ASSERT_EQ(nonfinite(img), 0u) << "case " << c;
        // A path's expected radiance is at most E_max / (1 - a_max); the image mean of 2304
        // samples stays below a generous multiple of it.
        double mean = 0.0;
        for (float v : img.rgb)
            mean += v;
        mean /= double(img.rgb.size());
        const double bound = max_emission / (1.0 - std::min(0.95f, max_albedo));
        EXPECT_LE(mean, 3.0 * bound) << "case " << c;
        EXPECT_GE(mean, 0.0) << "case " << c;
    }
}

}  // namespace
}  // namespace pathfarm::stress_test
