// Converging weighs each frame of a pixel by the samples it took (FrameView::sample_weights):
// a frame in which workload scaling gave a pixel three times the frame's spp counts as three
// frames of the running mean, and its history length says so (the extra-sample plan reads it).
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "coordinator/converge/temporal_accumulator.h"

namespace pathfarm::coord::sample_weights_test {
namespace {

constexpr int kSize = 16;

FrameView still_sky(std::vector<float> weights) {  // every centre ray misses: sky by direction
    FrameView v;
    v.camera.yfov_radians = glm::radians(40.0f);
    v.gbuffer.resize(kSize, kSize);
    v.sample_weights = std::move(weights);
    return v;
}

FloatImage flat(float value) {
    FloatImage img(kSize, kSize);
    for (float& c : img.rgb)
        c = value;
    return img;
}

TEST(SampleWeights, AFrameCountsAsManyFramesAsItsSamples) {
    std::vector<float> first(kSize * kSize);
    for (std::size_t i = 0; i < first.size(); ++i)
        first[i] = float(1 + i % 3);  // 1, 2 or 3 times the frame's spp
    TemporalAccumulator acc;
    FloatImage img = flat(1.0f);
    acc.blend(img, still_sky(first));
    for (std::size_t i = 0; i < first.size(); ++i)
        EXPECT_EQ(acc.history_frames()[i], first[i]) << "pixel " << i;
    img = flat(5.0f);
    acc.blend(img, still_sky({}));  // no weights: one frame each
    img = flat(2.0f);
    acc.blend(img, still_sky(std::vector<float>(kSize * kSize, 2.0f)));
    for (std::size_t i = 0; i < first.size(); ++i) {
        const float w = first[i];
        const float expected = (w * 1.0f + 1.0f * 5.0f + 2.0f * 2.0f) / (w + 3.0f);
        EXPECT_NEAR(img.rgb[3 * i], expected, 1e-5f) << "pixel " << i << " first weight " << w;
        EXPECT_EQ(acc.history_frames()[i], w + 3.0f) << "pixel " << i;
    }
}

}  // namespace
}  // namespace pathfarm::coord::sample_weights_test
