// Regression image: builtin:cornell at 64x64, 64 spp, seed 0 against tests/render/refs. This
// catches regressions; correctness comes from the furnace and estimator-agreement tests. Set
// PATHFARM_UPDATE_REFS=1 to rewrite the reference after an intended change.
#include <cstdlib>

#include <gtest/gtest.h>

#include "common/film/image_compare.h"
#include "common/film/image_io.h"
#include "common/scene/load/builtin_scenes.h"
#include "tests/support/render_helpers.h"
#include "tests/support/test_env.h"

namespace pathfarm {
namespace {

TEST(Reference, CornellBoxMatchesStoredImage) {
    const std::string ref_path = std::string(PATHFARM_TEST_REFS) + "/cornell_64x64_64spp.exr";
    test::RenderRequest r;
    r.width = r.height = 64;
    r.spp = 64;
    const FloatImage img = test::render(make_cornell_box(), r);
    ASSERT_EQ(count_nonfinite(img), 0u);
    if (std::getenv("PATHFARM_UPDATE_REFS") != nullptr) {
        ASSERT_TRUE(write_image(ref_path, img).ok());
        GTEST_SKIP() << "reference rewritten: " << ref_path;
    }
    auto ref = read_image(ref_path);
    ASSERT_TRUE(ref.ok()) << ref.error().message;
    const double error = rmse(img, *ref);
    if (error > 1e-3) {
        const std::string diff = test::scratch_dir() + "/cornell.diff.exr";
        FloatImage d(img.width, img.height);
        for (std::size_t i = 0; i < d.rgb.size(); ++i)
            d.rgb[i] = std::abs(img.rgb[i] - ref->rgb[i]);
        (void)write_image(diff, d);
        ADD_FAILURE() << "RMSE " << error << " against " << ref_path << "; difference written to "
                      << diff;
    }
}

}  // namespace
}  // namespace pathfarm
