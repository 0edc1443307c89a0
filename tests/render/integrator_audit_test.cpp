// The integrator audit after the tilted-light bias (docs/rendering.md, "Audit"): each place
// where a sample and its density, a normal or a medium could be taken in different frames has a
// test here, on both backends. Estimator agreement cannot see an error that light and BSDF
// sampling share (which face of a mirrored emitter emits), so those cases check the answer.
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_builder.h"
#include "common/scene/mesh.h"
#include "tests/support/render_helpers.h"

namespace pathfarm::integrator_audit_test {
namespace {

constexpr double kAlpha = 1e-3;

class IntegratorAudit : public ::testing::TestWithParam<tracer::BackendKind> {};

std::vector<FloatImage> batches(const SceneModel& scene, LightStrategy strategy, int spp,
                                uint32_t seed, tracer::BackendKind backend, int size = 24) {
    test::RenderRequest r;
    r.width = r.height = size;
    r.spp = spp;
    r.seed = seed;
    r.integrator.strategy = strategy;
    r.integrator.max_depth = 6;
    r.backend = backend;
    return test::render_seeds(scene, r, 16);
}

Camera look(const Vec3& from, const Vec3& at, float fov_degrees = 40.0f) {
    Camera cam;
    cam.yfov_radians = glm::radians(fov_degrees);
    cam.camera_to_world = glm::inverse(glm::lookAt(from, at, Vec3(0, 1, 0)));
    return cam;
}

double mean(const FloatImage& img) {
    double s = 0.0;
    for (float v : img.rgb)
        s += v;
    return s / double(img.rgb.size());
}

// glTF: a node transform with a negative determinant makes the winding clockwise, so a one-sided
// emitter emits along its *transformed* normal. A quad in the xy plane with front +z keeps its
// positions under scale(1, 1, -1) but must then emit towards -z; under scale(-1, 1, 1) it
// still emits towards +z. Seen head-on from the emitting side, a radiance-1 emitter is 1.0.
TEST_P(IntegratorAudit, MirroredEmitterEmitsAlongItsTransformedNormal) {
    struct Case {
        Vec3 scale;
        float emitting_side;  // +1: +z, -1: -z
    };
    for (const Case& c : {Case{{1, 1, 1}, 1.0f}, Case{{1, 1, -1}, -1.0f}, Case{{-1, 1, 1}, 1.0f},
                          Case{{-1, -1, -1}, -1.0f}}) {
        for (const float side : {1.0f, -1.0f}) {
            SceneBuilder b("mirrored-emitter");
            const int light = b.add_material(make_emitter("light", Rgb(1.0f)));
            b.add_instance(b.add_mesh(make_quad(Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0), light)),
                           glm::scale(Mat4(1.0f), c.scale));
            b.add_camera(look(Vec3(0, 0, 3.0f * side), Vec3(0.0f), 20.0f));
            b.environment().sky = SkyMode::off;
            test::RenderRequest r;
            r.width = r.height = 8;
            r.spp = 4;
            r.backend = GetParam();
            const double expected = side == c.emitting_side ? 1.0 : 0.0;
            EXPECT_NEAR(mean(test::render(b.finish(), r)), expected, 1e-4)
                << "scale " << c.scale.x << "," << c.scale.y << "," << c.scale.z << " seen from z "
                << 3.0f * side;
        }
    }
}

// The same seen through light sampling: a panel mirrored across its own plane renders, by every
// estimator, as the panel whose winding is flipped explicitly, and unlike the unmirrored one
// (which is what ignoring the determinant would give).
SceneModel panel_over_floor(const Mat4& panel_transform, bool flip_winding) {
    SceneBuilder b("mirrored-panel");
    const int floor = b.add_material(make_lambert("floor", Rgb(0.7f)));
    const int light = b.add_material(make_emitter("light", Rgb(4.0f)));
    b.add_instance(b.add_mesh(make_quad(Vec3(0.0f), Vec3(2, 0, 0), Vec3(0, 0, -2), floor)),
                   Mat4(1.0f));
    // make_quad(c, u, v) faces cross(u, v): -y here, towards the floor.
    Mesh panel = make_quad(Vec3(0.0f), Vec3(0.4f, 0, 0), Vec3(0, 0, 0.4f), light);
    if (flip_winding)
        for (std::size_t i = 0; i < panel.indices.size(); i += 3)
            std::swap(panel.indices[i + 1], panel.indices[i + 2]);
    b.add_instance(b.add_mesh(std::move(panel)),
                   glm::translate(Mat4(1.0f), Vec3(0, 1, 0)) * panel_transform);
    b.add_camera(look(Vec3(0, 2.5f, 3.0f), Vec3(0, 0, 0)));
    b.environment().sky = SkyMode::off;
    return b.finish();
}

TEST_P(IntegratorAudit, MirroredPanelRendersAsTheFlippedPanel) {
    // The panel lies in its node's plane y = 0: scaling y by -1 moves no vertex, it only makes
    // the determinant negative.
    const SceneModel mirrored = panel_over_floor(glm::scale(Mat4(1.0f), Vec3(1, -1, 1)), false);
    const SceneModel flipped = panel_over_floor(Mat4(1.0f), true);
    const SceneModel unmirrored = panel_over_floor(Mat4(1.0f), false);
    const auto be = GetParam();
    const auto mirrored_light = batches(mirrored, LightStrategy::light_only, 16, 10, be);
    const auto mirrored_bsdf = batches(mirrored, LightStrategy::bsdf_only, 32, 30, be);
    const auto flipped_light = batches(flipped, LightStrategy::light_only, 16, 50, be);
    const auto unmirrored_light = batches(unmirrored, LightStrategy::light_only, 16, 70, be);
    const auto as_flipped = test::compare_batches(mirrored_light, flipped_light, kAlpha, 4);
    EXPECT_TRUE(as_flipped.agree(kAlpha))
        << "mirrored vs flipped: min block p " << as_flipped.min_pixel_p << ", mean p "
        << as_flipped.mean_p;
    const auto estimators = test::compare_batches(mirrored_light, mirrored_bsdf, kAlpha, 4);
    EXPECT_TRUE(estimators.agree(kAlpha)) << "light vs bsdf: min block p " << estimators.min_pixel_p
                                          << ", mean p " << estimators.mean_p;
    EXPECT_FALSE(test::compare_batches(mirrored_light, unmirrored_light, kAlpha, 4).agree(kAlpha));
}

// Next-event estimation from a point inside an absorbing dielectric: the shadow segment
// crosses the medium too, so it is attenuated by Beer's law as the BSDF-sampled path is.
// An emitter inside a rough, absorbing glass ball: light and BSDF sampling agree.
TEST_P(IntegratorAudit, ShadowRaysInsideAnAbsorbingMediumAreAttenuated) {
    SceneBuilder b("lamp-in-tinted-glass");
    Material glass = make_lambert("glass", Rgb(1.0f));
    glass.transmission_factor = 1.0f;
    glass.specular_factor = 1.0f;
    glass.roughness_factor = 0.4f;
    glass.attenuation_color = Rgb(0.3f, 0.6f, 0.9f);
    glass.attenuation_distance = 0.5f;
    const int glass_mat = b.add_material(glass);
    const int light = b.add_material(make_emitter("core", Rgb(6.0f), true));
    const int floor = b.add_material(make_lambert("floor", Rgb(0.6f)));
    b.add_instance(b.add_mesh(make_quad(Vec3(0, -1, 0), Vec3(3, 0, 0), Vec3(0, 0, -3), floor)),
                   Mat4(1.0f));
    b.add_instance(b.add_mesh(make_sphere(1.0f, 24, 32, glass_mat)), Mat4(1.0f));
    b.add_instance(b.add_mesh(make_sphere(0.35f, 12, 16, light)), Mat4(1.0f));
    b.add_camera(look(Vec3(0, 1.0f, 3.5f), Vec3(0, -0.2f, 0), 50.0f));
    b.environment().sky = SkyMode::off;
    const SceneModel scene = b.finish();
    const auto light_only = batches(scene, LightStrategy::light_only, 32, 50, GetParam());
    const auto mis = batches(scene, LightStrategy::mis, 32, 70, GetParam());
    const auto bsdf_only = batches(scene, LightStrategy::bsdf_only, 64, 90, GetParam());
    // MIS and BSDF sampling have low variance here and are compared block by block. NEE alone
    // samples the caustic through the rough ball badly (rare, huge values: batch means too
    // skewed for a t-test per block), so it is compared on the image mean.
    const auto mb = test::compare_batches(mis, bsdf_only, kAlpha, 4);
    EXPECT_TRUE(mb.agree(kAlpha)) << "mis vs bsdf: min block p " << mb.min_pixel_p << " ("
                                  << mb.worst_a << " vs " << mb.worst_b << "), mean p "
                                  << mb.mean_p;
    const auto lb = test::compare_batches(light_only, bsdf_only, kAlpha, 4);
    EXPECT_GE(lb.mean_p, kAlpha) << "light vs bsdf image mean";
}

// A normal map whose texels all tilt "up" in the image (+Y, the glTF convention) on a quad
// facing the camera with the image upright, tangents generated as the loaders do: the surface
// must look brighter lit from above than from below, also under a mirroring node transform
// (the bitangent follows the determinant). The generated tangents used to flip this.
TEST_P(IntegratorAudit, NormalMapsTiltTowardsImageUp) {
    const auto render_lit_from = [&](float light_y, float mirror_x) {
        SceneBuilder b("tilted-normal-map");
        Image tilt{"tilt", 2, 2, std::vector<uint8_t>(16, 255)};
        for (int k = 0; k < 4; ++k) {  // tangent-space normal (0, 0.5, 0.87)
            tilt.rgba[4 * k] = 128;
            tilt.rgba[4 * k + 1] = 191;
            tilt.rgba[4 * k + 2] = 238;
        }
        Texture tex;
        tex.image = b.add_image(std::move(tilt));
        Material m = make_lambert("wall", Rgb(0.8f));
        m.normal_texture.texture = b.add_texture(tex);
        Mesh quad = make_quad(Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, -1, 0), b.add_material(m));
        std::swap(quad.indices[1], quad.indices[2]);  // (u, -v) faces -z: wind it towards +z
        std::swap(quad.indices[4], quad.indices[5]);
        quad.normals.assign(4, Vec3(0, 0, 1));
        quad.tangents.clear();
        compute_tangents(quad);  // as the loaders do without a TANGENT attribute
        b.add_instance(b.add_mesh(std::move(quad)), glm::scale(Mat4(1.0f), Vec3(mirror_x, 1, 1)));
        const int light = b.add_material(make_emitter("light", Rgb(20.0f)));
        // A small panel at height light_y in front of the wall, facing it.
        b.add_instance(b.add_mesh(make_quad(Vec3(0, light_y, 1.0f), Vec3(0.1f, 0, 0),
                                            Vec3(0, 0.1f, 0), light)),
                       glm::rotate(Mat4(1.0f), kPi, Vec3(0, 1, 0)) *
                           glm::translate(Mat4(1.0f), Vec3(0, 0, -2.0f)));
        b.add_camera(look(Vec3(0, 0, 3.0f), Vec3(0.0f), 20.0f));
        b.environment().sky = SkyMode::off;
        test::RenderRequest r;
        r.width = r.height = 8;
        r.spp = 64;
        r.integrator.strategy = LightStrategy::light_only;
        r.integrator.max_depth = 1;
        r.backend = GetParam();
        return mean(test::render(b.finish(), r));
    };
    for (const float mirror : {1.0f, -1.0f}) {
        const double above = render_lit_from(1.0f, mirror), below = render_lit_from(-1.0f, mirror);
        EXPECT_GT(above, 1.5 * below)
            << "mirror " << mirror << ": lit from above " << above << ", from below " << below;
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, IntegratorAudit, ::testing::ValuesIn(test::built_backends()),
                         test::BackendTestName());

}  // namespace
}  // namespace pathfarm::integrator_audit_test
