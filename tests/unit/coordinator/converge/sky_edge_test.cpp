// A sky pixel at a silhouette: its centre ray misses, some of its samples hit the object. Its
// history's variance is that edge's, not noise (the sky is exact sample by sample), so when the
// silhouette has gone the history clamp must not be widened by it: a widened clamp left a trail
// of brightened sky behind a moving figure's head for a dozen frames (Cesium Man's orbit).
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "coordinator/converge/temporal_accumulator.h"

namespace pathfarm::coord::sky_edge_test {
namespace {

constexpr int kSize = 32;
constexpr float kSky = 0.3f;

FrameView sky_view(int k) {  // all sky; the camera turns a hundredth of a degree a frame
    FrameView v;
    v.camera.yfov_radians = glm::radians(40.0f);
    v.camera.camera_to_world =
        glm::rotate(Mat4(1.0f), glm::radians(0.01f * float(k)), Vec3(0.0f, 1.0f, 0.0f));
    v.gbuffer.resize(kSize, kSize);
    return v;
}

bool in_band(int x) { return x >= 14 && x < 18; }

TEST(SkyEdge, AGoneSilhouetteLeavesNoTrailInTheSky) {
    TemporalAccumulator acc;
    for (int k = 0; k < 8; ++k) {  // an edge over the band: its samples hit a bright object or not
        FloatImage img(kSize, kSize);
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x)
                img.set_pixel(x, y, Rgb(in_band(x) && k % 2 == 0 ? 3.0f : kSky));
        acc.blend(img, sky_view(k));
    }
    FloatImage img(kSize, kSize);  // the object has gone: sky everywhere
    for (float& c : img.rgb)
        c = kSky;
    const ConvergeStats st = acc.blend(img, sky_view(8));
    EXPECT_GT(st.kept, 0.9) << "the sky reprojects by direction";
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            EXPECT_NEAR(img.pixel(x, y).x, kSky, 0.01f) << x << "," << y;
}

}  // namespace
}  // namespace pathfarm::coord::sky_edge_test
