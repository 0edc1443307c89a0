// A G-buffer written over a spare one (the accumulator's, two frames old) equals one made
// fresh: every plane of every pixel is written, whatever the spare held or its size.
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "coordinator/converge/gbuffer.h"
#include "coordinator/converge/temporal_accumulator.h"

namespace pathfarm::coord {
namespace {

std::vector<FirstHit> random_hits(int w, int h, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<FirstHit> hits(std::size_t(w) * std::size_t(h));
    for (FirstHit& f : hits) {
        if (u(rng) < 0.2f) continue;  // a miss
        f.distance = 1.0f + 10.0f * u(rng);
        f.instance = 1 + uint32_t(4.0f * u(rng));
        f.normal = glm::normalize(Vec3(u(rng) - 0.5f, u(rng), u(rng) - 0.5f) + Vec3(0, 0.1f, 0));
        f.albedo = Rgb(u(rng), u(rng), u(rng));
        f.flags = uint32_t(8.0f * u(rng)) & 7u;
        f.primitive = u(rng) < 0.5f ? FirstHit::kNone : uint32_t(1000.0f * u(rng));
        f.u = u(rng), f.v = u(rng);
    }
    return hits;
}

void expect_equal(const GBuffer& a, const GBuffer& b) {
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.distance, b.distance);
    EXPECT_EQ(a.instance, b.instance);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.albedo, b.albedo);
    EXPECT_EQ(a.sharp, b.sharp);
    EXPECT_EQ(a.glossy, b.glossy);
    EXPECT_EQ(a.primitive, b.primitive);
    EXPECT_EQ(a.barycentric, b.barycentric);
}

TEST(GBufferReuse, WrittenOverASpareItEqualsAFreshOne) {
    std::mt19937 rng(31);
    Camera camera;
    camera.camera_to_world = glm::translate(Mat4(1.0f), Vec3(0.3f, 1.0f, 4.0f));
    for (const auto& [spare_w, spare_h] :
         {std::pair{40, 30}, std::pair{37, 21}, std::pair{80, 45}}) {
        const std::vector<FirstHit> hits = random_hits(33, 19, rng);  // upscaled to 40x30
        const GBuffer fresh = gbuffer_from_first_hits(hits, 33, 19, camera, 40, 30);
        GBuffer spare = gbuffer_from_first_hits(random_hits(spare_w, spare_h, rng), spare_w,
                                                spare_h, camera, spare_w, spare_h);
        expect_equal(gbuffer_from_first_hits(hits, 33, 19, camera, 40, 30, std::move(spare)),
                     fresh);
    }
}

// The accumulator hands back the G-buffer of the frame before the last, once.
TEST(GBufferReuse, TheAccumulatorsSpareIsTheFrameBeforeTheLast) {
    std::mt19937 rng(37);
    TemporalAccumulator acc;
    Camera camera;
    EXPECT_TRUE(acc.take_spare_gbuffer().distance.empty());
    std::vector<GBuffer> made;
    for (int f = 0; f < 3; ++f) {
        FloatImage image(16, 9);
        FrameView view;
        view.camera = camera;
        view.gbuffer = gbuffer_from_first_hits(random_hits(16, 9, rng), 16, 9, camera, 16, 9);
        view.instances = {{1, Mat4(1.0f)}, {2, Mat4(1.0f)}, {3, Mat4(1.0f)}, {4, Mat4(1.0f)}};
        made.push_back(view.gbuffer);
        acc.blend(image, std::move(view));
        if (f == 0) {
            EXPECT_TRUE(acc.take_spare_gbuffer().distance.empty());
        }
    }
    expect_equal(acc.take_spare_gbuffer(), made[1]);  // frame 2 replaced frame 1's
    EXPECT_TRUE(acc.take_spare_gbuffer().distance.empty()) << "handed back once";
}

}  // namespace
}  // namespace pathfarm::coord
