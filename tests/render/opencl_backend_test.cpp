// The OpenCL backend (on PoCL here) against the Embree backend: per-pixel statistical
// agreement over independent seeds (Welch tests, Šidák-corrected, as estimator_agreement_test),
// the analytic furnace, bit-identical results for any row split, and incremental uploads.
#include <cstring>

#include <gtest/gtest.h>

#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/scene_loader.h"
#include "tests/support/render_helpers.h"
#include "tests/support/test_env.h"
#include "tracer-node/opencl/device_scene.h"
#include "tracer-node/opencl/opencl_backend.h"

namespace pathfarm::opencl_backend_test {
namespace {

using tracer::BackendKind;

constexpr double kAlpha = 0.01;
constexpr int kBatches = 16;

// kBatches images of seeds 5000, 5001, ... (Embree) or 5500, ... (OpenCL), from one backend:
// a backend per image packed and uploaded the Damaged Helmet's textures 32 times (33 s of
// the test's time, 13 s of it in the kernel).
std::vector<FloatImage> batches(const SceneModel& scene, BackendKind backend, int spp, int width,
                                int height) {
    test::RenderRequest r;
    r.width = width;
    r.height = height;
    r.spp = spp;
    // Independent seeds per backend: the two backends draw the same numbers for the same
    // seed, which would make the comparison trivially pass.
    r.seed = 5000 + (backend == BackendKind::opencl ? 500 : 0);
    r.integrator.max_depth = 6;
    r.backend = backend;
    return test::render_seeds(scene, r, kBatches);
}

void expect_agreement(const SceneModel& scene, int spp, int width, int height, int block = 1) {
    const auto embree = batches(scene, BackendKind::embree, spp, width, height);
    const auto opencl = batches(scene, BackendKind::opencl, spp, width, height);
    const auto r = test::compare_batches(embree, opencl, kAlpha, block);
    EXPECT_TRUE(r.agree(kAlpha)) << scene.name << ": min pixel p " << r.min_pixel_p
                                 << " (threshold " << r.pixel_threshold << "), mean p " << r.mean_p
                                 << "; worst value " << r.worst_value << ": " << r.worst_a
                                 << " (embree) vs " << r.worst_b << " (opencl)";
}

TEST(OpenClBackend, CornellBoxAgreesWithEmbree) {
    expect_agreement(make_cornell_box(), 16, 24, 24);
}

TEST(OpenClBackend, DefaultSceneAgreesWithEmbree) {
    // Glossy, metal, glass with absorption, a texture, sun and sky, several lights.
    expect_agreement(make_default_scene(), 8, 24, 16);
}

TEST(OpenClBackend, TexturedHelmetAgreesWithEmbree) {
    // Base colour, metal-roughness, normal and emissive textures (glTF).
    PF_REQUIRE_SCENES(dir);
    auto scene = load_scene(dir + "/damaged-helmet/DamagedHelmet.gltf");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    expect_agreement(*scene, 8, 24, 24);
}

TEST(OpenClBackend, SibenikAgreesWithEmbree) {
    // 75k triangles from an OBJ: deep BVHs and many materials.
    PF_REQUIRE_SCENES(dir);
    auto scene = load_scene(dir + "/sibenik/sibenik.obj");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    expect_agreement(*scene, 8, 24, 16, 2);
}

TEST(OpenClBackend, DetectsASmallBias) {
    // The comparison must reject a 3 % brighter OpenCL image.
    const SceneModel scene = make_cornell_box();
    const auto embree = batches(scene, BackendKind::embree, 16, 24, 24);
    auto opencl = batches(scene, BackendKind::opencl, 16, 24, 24);
    for (FloatImage& img : opencl)
        for (float& v : img.rgb)
            v *= 1.03f;
    EXPECT_FALSE(test::compare_batches(embree, opencl, kAlpha).agree(kAlpha));
}

TEST(OpenClBackend, FurnaceIsEmissionOverOneMinusAlbedo) {
    const SceneModel scene = test::make_furnace(0.5f, 0.5f);
    test::RenderRequest r;
    r.spp = 64;
    r.integrator.max_depth = 100;
    r.backend = BackendKind::opencl;
    const FloatImage img = test::render(scene, r);
    double sum = 0.0, max_dev = 0.0;
    for (float v : img.rgb) {
        ASSERT_TRUE(std::isfinite(v));
        sum += v;
        max_dev = std::max(max_dev, std::abs(double(v) - 1.0));
    }
    EXPECT_NEAR(sum / double(img.rgb.size()), 1.0, 0.01);
    EXPECT_LT(max_dev, 0.2);
}

TEST(OpenClBackend, AnyRowSplitGivesTheSameImage) {
    const SceneModel scene = make_default_scene();
    test::RenderRequest r;
    r.width = 40;
    r.height = 24;
    r.spp = 4;
    r.backend = BackendKind::opencl;
    const FloatImage whole = test::render(scene, r);
    r.row_splits = {1, 7, 20};
    const FloatImage split = test::render(scene, r);
    ASSERT_EQ(whole.rgb.size(), split.rgb.size());
    EXPECT_EQ(std::memcmp(whole.rgb.data(), split.rgb.data(), whole.rgb.size() * sizeof(float)), 0);
}

// Fraction of channel values the two images share within a float rounding's reach.
double close_fraction(const FloatImage& a, const FloatImage& b) {
    std::size_t close = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i)
        close += std::abs(a.rgb[i] - b.rgb[i]) <= 1e-4f * (1.0f + a.rgb[i]);
    return double(close) / double(a.rgb.size());
}

TEST(OpenClBackend, SameSeedGivesNearlyTheSameImageAsEmbree) {
    // Same per-sample random numbers: paths only part where float rounding differs (a ray
    // grazing an edge, a roulette draw at the threshold), so almost every pixel matches.
    const SceneModel scene = make_cornell_box();
    test::RenderRequest r;
    r.width = r.height = 32;
    r.spp = 8;
    const FloatImage embree = test::render(scene, r);
    r.backend = BackendKind::opencl;
    const FloatImage opencl = test::render(scene, r);
    EXPECT_GT(close_fraction(embree, opencl), 0.99);
}

// Among 2 048 emitters chosen by power, the kernel's search through the guide table must answer
// as the host's GuidedCdf (both as std::upper_bound): with the same random numbers the two
// backends then light almost every pixel alike. A guide read one bucket off, or the narrowed
// search's answer taken unchecked, chooses other emitters in most paths.
TEST(OpenClBackend, PowerSamplingChoosesEmbreesEmittersAmongThousands) {
    const SceneModel scene = make_many_lights_scene();
    test::RenderRequest r;
    r.width = r.height = 32;
    r.spp = 8;
    r.integrator.light_selection = LightSelection::power;
    const FloatImage embree = test::render(scene, r);
    r.backend = BackendKind::opencl;
    const FloatImage opencl = test::render(scene, r);
    EXPECT_GT(close_fraction(embree, opencl), 0.99);
}

TEST(OpenClBackend, ChoosesTheSameTextureLevelsAsEmbree) {
    // The default scene's floor texture seen after bounces: with the same random numbers both
    // backends must read the same mip level of the same texels (device_scene.cpp packs them,
    // the kernel finds them). A kernel reading level 0 instead, as with --texture-lod off on
    // one side, leaves far fewer pixels alike; that case is measured too, so the test shows
    // it can tell.
    const SceneModel scene = make_default_scene();
    test::RenderRequest r;
    r.width = 48;
    r.height = 32;
    r.spp = 4;
    const FloatImage embree = test::render(scene, r);
    r.backend = BackendKind::opencl;
    const FloatImage opencl = test::render(scene, r);
    r.texture_lod = false;
    const FloatImage opencl_flat = test::render(scene, r);
    const double alike = close_fraction(embree, opencl);
    const double alike_flat = close_fraction(embree, opencl_flat);
    EXPECT_GT(alike, 0.99);
    EXPECT_LT(alike_flat, 0.9) << "level 0 everywhere looks as alike: " << alike_flat;
}

FloatImage render_rows(tracer::RenderBackend& backend, const SceneModel& scene, int w, int h) {
    tracer::RenderJob job;
    job.frame =
        FrameSpec{w,
                  h,
                  0,
                  7,
                  4,
                  0,
                  scene.cameras.empty() ? frame_bounds(world_bounds(scene), float(w) / float(h))
                                        : scene.cameras[0]};
    job.y0 = 0;
    job.y1 = h;
    FloatImage image(w, h);
    auto stats = backend.render_rows(job, image.row(0));
    EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
    return image;
}

TEST(OpenClBackend, MovingOneInstanceUploadsOnlyThatInstance) {
    auto made = tracer::make_opencl_backend({});
    ASSERT_TRUE(made.ok()) << made.error().message;
    tracer::OpenClBackend& backend = **made;
    SceneModel scene = make_default_scene();
    ASSERT_TRUE(backend.set_scene(scene).ok());
    const std::size_t first = backend.last_upload().total();
    EXPECT_GT(first, 100000u);  // everything, the first time

    ASSERT_TRUE(backend.set_scene(scene).ok());
    EXPECT_EQ(backend.last_upload().total(), 0u) << "an unchanged scene uploads nothing";

    // Move a non-emissive instance a little (its box stays inside the top level's root box).
    std::size_t moved = scene.instances.size();
    for (std::size_t i = 0; i < scene.instances.size(); ++i)
        if (!scene
                 .materials[std::size_t(
                     scene.meshes[std::size_t(scene.instances[i].mesh)].material)]
                 .is_emissive()) {
            moved = i;
            break;
        }
    ASSERT_LT(moved, scene.instances.size());
    scene.instances[moved].transform =
        glm::translate(Mat4(1.0f), Vec3(0.05f, 0.0f, 0.0f)) * scene.instances[moved].transform;
    ASSERT_TRUE(backend.set_scene(scene).ok());
    const auto& up = backend.last_upload().bytes;
    EXPECT_EQ(up.at("instances"), sizeof(PfInstance));
    for (const char* untouched : {"positions", "normals", "uvs", "tangents", "indices", "nodes",
                                  "prims", "materials", "texels", "lights"})
        EXPECT_EQ(up.at(untouched), 0u) << untouched;
    // The top level is rebuilt over the instance boxes: only nodes that changed go up.
    EXPECT_LE(up.at("top_nodes"), scene.instances.size() * 2 * sizeof(PfBvhNode));
    EXPECT_LT(backend.last_upload().total(), 2000u);
    RecordProperty("bytes_after_move", int(backend.last_upload().total()));

    // What the device holds now renders exactly what a fresh backend renders.
    auto fresh = tracer::make_opencl_backend({});
    ASSERT_TRUE(fresh.ok());
    ASSERT_TRUE((*fresh)->set_scene(scene).ok());
    const FloatImage a = render_rows(backend, scene, 32, 20);
    const FloatImage b = render_rows(**fresh, scene, 32, 20);
    EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0);
}

TEST(OpenClBackend, UsesProvidedBvhsAndRejectsBrokenOnes) {
    const SceneModel scene = make_cornell_box();
    std::vector<Bvh> built;
    for (const Mesh& m : scene.meshes)
        built.push_back(build_bvh(m.positions, m.indices));
    auto made = tracer::make_opencl_backend({});
    ASSERT_TRUE(made.ok()) << made.error().message;
    std::vector<tracer::MeshBvhView> views;
    for (const Bvh& b : built)
        views.push_back({&b.nodes, &b.prim_indices});
    (*made)->provide_mesh_bvhs(views);
    ASSERT_TRUE((*made)->set_scene(scene).ok());
    EXPECT_EQ((*made)->meshes_with_own_bvh(), 0u);

    built[0].prim_indices[0] = 1000000;  // a primitive the mesh does not have
    built[1].nodes[0].first = 9999;      // a child past the end
    (*made)->provide_mesh_bvhs(views);
    ASSERT_TRUE((*made)->set_scene(scene).ok());
    EXPECT_EQ((*made)->meshes_with_own_bvh(), 2u);
    const FloatImage img = render_rows(**made, scene, 16, 16);
    for (float v : img.rgb)
        ASSERT_TRUE(std::isfinite(v));
}

TEST(OpenClBackend, OutOfRangeDeviceIsAOneLineError) {
    tracer::BackendOptions o;
    o.cl_platform = 7;
    auto made = tracer::make_opencl_backend(o);
    ASSERT_FALSE(made.ok());
    EXPECT_NE(made.error().message.find("--cl-platform 7: out of range"), std::string::npos)
        << made.error().message;
    o.cl_platform = 0;
    o.cl_device = 5;
    made = tracer::make_opencl_backend(o);
    ASSERT_FALSE(made.ok());
    EXPECT_NE(made.error().message.find("--cl-device 5: out of range"), std::string::npos);
}

}  // namespace
}  // namespace pathfarm::opencl_backend_test
