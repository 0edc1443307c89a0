// A tracer's first hits of a frame, made into the farm's G-buffer.
#include "tests/support/gbuffer_helpers.h"

#include <gtest/gtest.h>

#include "common/scene/scene_state.h"
#include "coordinator/scene_graph/scene_graph.h"
#include "tracer-node/backend/render_backend.h"

namespace pathfarm::test {

coord::GBuffer first_hit_gbuffer(const SceneModel& scene, const Camera& camera, uint32_t k,
                                 int display_w, int display_h, float scale) {
    const coord::SceneGraph graph(scene);
    return first_hit_gbuffer(graph.state(), camera, k, display_w, display_h, scale);
}

coord::GBuffer first_hit_gbuffer(const SceneState& state, const Camera& camera, uint32_t k,
                                 int display_w, int display_h, float scale) {
    const int w = int(display_w * scale), h = int(display_h * scale);
    SceneModel model = to_scene_model(state);
    model.cameras.at(0) = camera;
    recentre_on_camera(model, camera);
    auto backend = tracer::create_backend(tracer::BackendKind::embree, {2, 0, 0});
    EXPECT_TRUE(backend.ok() && (*backend)->set_scene(model).ok());
    std::vector<float> rgb(std::size_t(w) * h * 3);
    std::vector<FirstHit> hits(std::size_t(w) * h);
    const tracer::RenderJob job{FrameSpec{w, h, k, 7, 1, 0, model.cameras.at(0)},
                                IntegratorSettings{},
                                0,
                                h,
                                {},
                                hits.data()};
    EXPECT_TRUE((*backend)->render_rows(job, rgb.data()).ok());
    for (FirstHit& hit : hits)  // as the tracer sends them: the scene graph's ids
        if (hit.hit()) hit.instance = model.instances.at(hit.instance).id;
    return coord::gbuffer_from_first_hits(hits, w, h, camera, display_w, display_h);
}

}  // namespace pathfarm::test
