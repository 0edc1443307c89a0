// Converging and denoising keep a moving view's brightness where the light arrives as sparse
// samples (Sponza lit through its roof: at 1 spp most pixels see no light, a few see much).
// Clamping the history to such a frame's 3x3 neighbourhood once darkened the converged image of
// a walk to 0.44 of the reference; random walks through Sponza now stay within 15 %.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/scene/load/scene_loader.h"
#include "coordinator/converge/denoiser.h"
#include "tests/support/test_env.h"
#include "tracer-node/backend/render_backend.h"

namespace pathfarm::coord::moving_camera_energy_test {
namespace {

constexpr int kW = 64, kH = 36;

double mean(const FloatImage& image) {
    double sum = 0.0;
    for (float v : image.rgb)
        sum += v;
    return sum / double(image.rgb.size());
}

struct Walk {
    tracer::RenderBackend& backend;
    const SceneModel& scene;

    FloatImage render(const Camera& camera, uint32_t frame, uint32_t seed, int spp,
                      std::vector<FirstHit>* hits) const {
        FloatImage image(kW, kH);
        if (hits) hits->assign(std::size_t(kW) * kH, FirstHit{});
        const tracer::RenderJob job{FrameSpec{kW, kH, frame, seed, spp, 0, camera},
                                    IntegratorSettings{},
                                    0,
                                    kH,
                                    {},
                                    hits ? hits->data() : nullptr};
        EXPECT_TRUE(backend.render_rows(job, image.rgb.data()).ok());
        return image;
    }

    FrameView view(const Camera& camera, const std::vector<FirstHit>& hits) const {
        FrameView v;
        v.camera = camera;
        v.gbuffer = gbuffer_from_backend_hits(hits, camera, kW, kH);
        for (std::size_t i = 0; i < scene.instances.size(); ++i)
            v.instances[uint32_t(i + 1)] = scene.instances[i].transform;
        return v;
    }
};

TEST(MovingCamera, ConvergingAndDenoisingKeepTheBrightnessOfSparseLight) {
    PF_REQUIRE_SCENES(scenes);
    auto scene = load_scene(scenes + "/dabrovic-sponza/sponza.obj");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    auto backend = tracer::create_backend(tracer::BackendKind::embree, {2, 0, 0});
    ASSERT_TRUE(backend.ok() && (*backend)->set_scene(*scene).ok());
    const Walk walk{**backend, *scene};
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int trial = 0; trial < 3; ++trial) {
        // A walk along the nave, random start, heading and sway.
        const Vec3 start(-8.0f + 3.0f * u(rng), 1.5f + 0.5f * u(rng), 0.8f * u(rng));
        const Vec3 heading = glm::normalize(Vec3(1.0f, 0.1f * u(rng), 0.3f * u(rng)));
        TemporalAccumulator accumulator;
        Denoiser denoiser;
        FloatImage converged, denoised;
        Camera camera;
        for (int k = 0; k < 12; ++k) {
            const Vec3 eye = start + 0.2f * float(k) * heading;
            camera.camera_to_world = glm::inverse(
                glm::lookAt(eye, eye + heading + Vec3(0, 0.2f, 0), Vec3(0.0f, 1.0f, 0.0f)));
            std::vector<FirstHit> hits;
            const FloatImage raw = walk.render(camera, uint32_t(k), 1, 1, &hits);
            converged = raw;
            denoised = raw;
            accumulator.blend(converged, walk.view(camera, hits));
            denoiser.filter(denoised, walk.view(camera, hits), true);
        }
        const double reference = mean(walk.render(camera, 12, 77, 256, nullptr));
        SCOPED_TRACE(::testing::Message() << "walk " << trial);
        ASSERT_GT(reference, 0.0);
        EXPECT_NEAR(mean(converged) / reference, 1.0, 0.15);
        // The denoiser loses some sparse light (a known limit, docs/denoise.md): a bright
        // pixel's wide luminance tolerance averages it with its dark neighbours, whose narrow
        // ones do not take its light. These walks: 0.863, 0.971, 0.917 of the reference with
        // the centre's base colour, 0.843, 0.957, 0.889 with the footprint's (2026-12-03).
        EXPECT_NEAR(mean(denoised) / reference, 1.0, 0.17);
    }
}

}  // namespace
}  // namespace pathfarm::coord::moving_camera_energy_test
