// FrameSpec::extra_samples on every backend: a pixel given k samples beyond spp renders what it
// would at spp + k (its next samples, not other ones), whichever rows a call covers, and the
// counters count them. This is what keeps a frame with extra samples bit-exact for any split
// (docs/determinism.md).
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "common/scene/load/builtin_scenes.h"
#include "tests/support/render_helpers.h"

namespace pathfarm {
namespace {

constexpr int kW = 24, kH = 20;

class ExtraSamples : public ::testing::TestWithParam<tracer::BackendKind> {
protected:
    void SetUp() override {
        scene_ = make_default_scene();
        camera_ = recentre_on_camera(scene_, scene_.cameras.at(0));
        auto made = tracer::create_backend(GetParam(), tracer::BackendOptions{2, 0, 0});
        ASSERT_TRUE(made.ok()) << made.error().message;
        backend_ = std::move(*made);
        ASSERT_TRUE(backend_->set_scene(scene_).ok());
        std::mt19937 rng(17);
        map_.resize(std::size_t(kW) * kH);
        for (uint8_t& e : map_)
            e = uint8_t(rng() % 4);
    }

    // Rows [y0, y1) at `spp`, with the map or without, into their place in `rgb`.
    uint64_t render(std::vector<float>& rgb, int spp, bool with_map, int y0, int y1) {
        FrameSpec spec{kW, kH, 5, 9, spp, 0, camera_};
        if (with_map) spec.extra_samples = map_.data();
        tracer::RenderJob job{spec, IntegratorSettings{}, y0, y1, {}};
        rgb.resize(std::size_t(kW) * kH * 3);
        auto stats = backend_->render_rows(job, rgb.data() + std::size_t(y0) * kW * 3);
        EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
        return stats.ok() ? stats->counters.camera_samples : 0;
    }

    SceneModel scene_;
    Camera camera_;
    std::unique_ptr<tracer::RenderBackend> backend_;
    std::vector<uint8_t> map_;
};

TEST_P(ExtraSamples, APixelsExtraSamplesAreTheNextOnesItWouldTake) {
    std::vector<float> mapped;
    const uint64_t samples = render(mapped, 1, true, 0, kH);
    uint64_t expected_samples = 0;
    for (const uint8_t e : map_)
        expected_samples += 1u + e;
    EXPECT_EQ(samples, expected_samples);
    int checked[4] = {};
    for (int k = 0; k < 4; ++k) {
        std::vector<float> uniform;
        render(uniform, 1 + k, false, 0, kH);
        for (std::size_t p = 0; p < map_.size(); ++p) {
            if (map_[p] != k) continue;
            EXPECT_EQ(std::memcmp(&mapped[3 * p], &uniform[3 * p], 3 * sizeof(float)), 0)
                << "pixel " << p % kW << "," << p / kW << " with " << k << " extra samples";
            ++checked[k];
        }
    }
    for (int k = 0; k < 4; ++k)
        EXPECT_GT(checked[k], 50) << k;
}

TEST_P(ExtraSamples, AnyRowSplitGivesTheSameBits) {
    std::vector<float> whole, split;
    render(whole, 1, true, 0, kH);
    render(split, 1, true, 0, 7);
    render(split, 1, true, 7, 13);
    render(split, 1, true, 13, kH);
    EXPECT_EQ(std::memcmp(whole.data(), split.data(), whole.size() * sizeof(float)), 0);
    std::vector<float> plain;
    render(plain, 1, false, 0, kH);
    EXPECT_NE(std::memcmp(whole.data(), plain.data(), whole.size() * sizeof(float)), 0)
        << "the map must change the image";
}

INSTANTIATE_TEST_SUITE_P(Backends, ExtraSamples, ::testing::ValuesIn(test::built_backends()),
                         test::BackendTestName());

}  // namespace
}  // namespace pathfarm
