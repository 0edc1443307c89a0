// DESIGN.md determinism contract: the same frame is the same image, bit for bit, for any thread
// count and any row split (docs/determinism.md).
#include <cstring>

#include <gtest/gtest.h>

#include "common/scene/load/builtin_scenes.h"
#include "tests/support/render_helpers.h"
#include "tracer-node/backend/render_backend.h"

namespace pathfarm {
namespace {

bool bit_identical(const FloatImage& a, const FloatImage& b) {
    return a.rgb.size() == b.rgb.size() &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// A tracer renders a whole tile in one call when the backend times its units (the Embree
// backend): the rows equal one call per unit, bit for bit; each unit reports its own cost and
// rays; the stop check leaves the asked unit and every later one unrendered, and reports them so.
TEST(UnitTimedRanges, OneCallEqualsOneCallPerUnitAndStopsWhereAsked) {
    SceneModel scene = make_default_scene();
    const Camera camera = recentre_on_camera(scene, scene.cameras.at(0));
    auto backend = tracer::create_backend(tracer::BackendKind::embree, {2, 0, 0});
    ASSERT_TRUE(backend.ok());
    ASSERT_TRUE((*backend)->times_units());
    ASSERT_TRUE((*backend)->set_scene(scene).ok());
    tracer::RenderJob job{FrameSpec{40, 30, 2, 5, 2, 0, camera}, IntegratorSettings{}, 8, 24, {}};
    const std::size_t row = 40 * 3;
    std::vector<float> whole(16 * row), units(16 * row, -1.0f);
    auto stats = (*backend)->render_rows(job, whole.data());
    ASSERT_TRUE(stats.ok());
    ASSERT_EQ(stats->units.size(), 4u);
    for (const tracer::UnitStats& u : stats->units) {
        EXPECT_TRUE(u.rendered);
        EXPECT_GT(u.seconds, 0.0);
        EXPECT_GT(u.rays, 0u);
    }
    for (int y = 8; y < 24; y += 4) {
        tracer::RenderJob one = job;
        one.y0 = y;
        one.y1 = y + 4;
        ASSERT_TRUE((*backend)->render_rows(one, units.data() + std::size_t(y - 8) * row).ok());
    }
    EXPECT_EQ(std::memcmp(whole.data(), units.data(), whole.size() * sizeof(float)), 0);

    std::vector<float> cut(16 * row, -1.0f);
    job.stop = [](int unit_y0) { return unit_y0 >= 16; };
    stats = (*backend)->render_rows(job, cut.data());
    ASSERT_TRUE(stats.ok());
    ASSERT_EQ(stats->units.size(), 4u);
    EXPECT_TRUE(stats->units[0].rendered && stats->units[1].rendered);
    EXPECT_FALSE(stats->units[2].rendered || stats->units[3].rendered);
    EXPECT_EQ(std::memcmp(cut.data(), whole.data(), 8 * row * sizeof(float)), 0);
    EXPECT_EQ(cut[8 * row], -1.0f) << "rows from the stop on are left alone";
}

class Determinism : public ::testing::TestWithParam<const char*> {};

TEST_P(Determinism, ThreadsAndRowSplitsGiveIdenticalImages) {
    const SceneModel scene =
        std::string(GetParam()) == "cornell" ? make_cornell_box() : make_default_scene();
    test::RenderRequest r;
    r.width = 40;
    r.height = 27;
    r.spp = 4;
    r.seed = 7;
    r.frame = 3;
    r.threads = 1;
    const FloatImage one = test::render(scene, r);
    r.threads = 2;
    EXPECT_TRUE(bit_identical(one, test::render(scene, r))) << "1 vs 2 threads";
    r.row_splits = {5, 6, 19};
    EXPECT_TRUE(bit_identical(one, test::render(scene, r))) << "odd row split";
    r.row_splits = {};
    r.seed = 8;
    EXPECT_FALSE(bit_identical(one, test::render(scene, r)))
        << "another seed must change the image";
}

INSTANTIATE_TEST_SUITE_P(Scenes, Determinism, ::testing::Values("cornell", "default"));

}  // namespace
}  // namespace pathfarm

namespace pathfarm {
namespace {

// The loop specialised for a scene's features leaves out only work that would change nothing:
// its image is the generic loop's, bit for bit, on scenes with and without each feature.
TEST(SpecialisedKernel, ImageEqualsTheGenericLoopBitForBit) {
    for (const char* name : {"cornell", "default", "glass", "many-lights"}) {
        const SceneModel scene = make_builtin_scene(name).value();
        test::RenderRequest r;
        r.width = r.height = 24;
        r.spp = 4;
        const FloatImage specialised = test::render(scene, r);
        r.integrator.specialise = false;
        const FloatImage generic = test::render(scene, r);
        EXPECT_EQ(specialised.rgb, generic.rgb) << name;
    }
}

}  // namespace
}  // namespace pathfarm
