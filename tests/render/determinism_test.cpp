// DESIGN.md determinism contract: the same frame is the same image, bit for bit, for any thread
// count and any row split (docs/determinism.md).
#include <cstring>

#include <gtest/gtest.h>

#include "common/scene/load/builtin_scenes.h"
#include "tests/support/render_helpers.h"

namespace pathfarm {
namespace {

bool bit_identical(const FloatImage& a, const FloatImage& b) {
    return a.rgb.size() == b.rgb.size() &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
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
