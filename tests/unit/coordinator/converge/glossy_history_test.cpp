// Glossy surfaces under a turning camera: builtin:default's marble pillars and gold spheres
// reflect the room, and their reflections move over them as the camera turns, so history
// reprojected with the surface lags. The tracers flag them (FirstHit::kGlossy); the denoiser's
// accumulator keeps at most 1 / DenoiseOptions::glossy_floor frames of it there, while
// converging keeps its camera floor's longer history.
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/scene/load/builtin_scenes.h"
#include "coordinator/converge/denoiser.h"
#include "tracer-node/backend/render_backend.h"

namespace pathfarm::coord::glossy_history_test {
namespace {

constexpr int kW = 96, kH = 54;

TEST(GlossyHistory, TheDenoiserKeepsAtMostItsGlossyFloorsHistoryWhereTheCameraTurns) {
    const SceneModel scene = make_default_scene();
    auto backend = tracer::create_backend(tracer::BackendKind::embree, {2, 0, 0});
    ASSERT_TRUE(backend.ok() && (*backend)->set_scene(scene).ok());
    const DenoiseOptions options;
    const ConvergeOptions converge;
    ASSERT_GT(options.glossy_floor, converge.camera_floor);
    Denoiser denoiser(options);
    TemporalAccumulator converging(converge);
    FrameView view;
    for (int k = 0; k <= 12; ++k) {
        Camera camera = scene.cameras.at(0);
        camera.camera_to_world = glm::rotate(camera.camera_to_world, glm::radians(0.3f * float(k)),
                                             Vec3(0.0f, 1.0f, 0.0f));
        FloatImage image(kW, kH);
        std::vector<FirstHit> hits(std::size_t(kW) * kH);
        const tracer::RenderJob job{FrameSpec{kW, kH, uint32_t(k), 3, 1, 0, camera},
                                    IntegratorSettings{},
                                    0,
                                    kH,
                                    {},
                                    hits.data()};
        ASSERT_TRUE((*backend)->render_rows(job, image.rgb.data()).ok());
        view = FrameView{};
        view.camera = camera;
        view.gbuffer = gbuffer_from_backend_hits(hits, camera, kW, kH);
        for (std::size_t i = 0; i < scene.instances.size(); ++i)
            view.instances[uint32_t(i + 1)] = scene.instances[i].transform;
        FloatImage converged = image;
        converging.blend(converged, view);
        denoiser.filter(image, view, true);
    }
    int glossy = 0, floored = 0, longer_converging = 0, plain = 0, plain_longer = 0;
    for (std::size_t i = 0; i < view.gbuffer.glossy.size(); ++i) {
        const float frames = denoiser.history_frames()[i];
        if (!view.gbuffer.glossy[i]) {
            plain += view.gbuffer.hit(i) && !view.gbuffer.sharp[i];
            plain_longer += view.gbuffer.hit(i) && !view.gbuffer.sharp[i] &&
                            frames > 1.0f / options.glossy_floor + 1e-3f;
            continue;
        }
        ++glossy;
        EXPECT_LE(frames, 1.0f / options.glossy_floor + 1e-3f) << "pixel " << i;
        floored += frames > 1.0f / options.glossy_floor - 1e-3f;
        longer_converging += converging.history_frames()[i] > 1.0f / options.glossy_floor + 1e-3f;
    }
    EXPECT_GT(glossy, 300) << "the pillars and the gold spheres";
    EXPECT_GT(floored, glossy / 2);
    EXPECT_GT(longer_converging, glossy / 2) << "converging keeps its own floor";
    EXPECT_GT(plain_longer, plain / 2) << "other surfaces keep the camera floor's history";
}

}  // namespace
}  // namespace pathfarm::coord::glossy_history_test
