// The denoiser on real renders of builtin:default (Embree backend) with the G-buffer the farm
// makes from the tracers' first hits, against a converged reference: a converged image stays
// itself, a noisy frame and a still sequence come out much closer to the reference than they
// went in (and than converging alone).
#include <gtest/gtest.h>

#include "common/film/image_compare.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/scene_state.h"
#include "coordinator/converge/denoiser.h"
#include "coordinator/scene_graph/scene_graph.h"
#include "tests/support/gbuffer_helpers.h"
#include "tests/support/render_helpers.h"

namespace pathfarm::coord::denoiser_test {
namespace {

constexpr int kW = 48, kH = 48;

struct Still {
    SceneModel scene = make_cornell_box();
    FrameView view;
    Still() {
        view.camera = scene.cameras.at(0);
        // The scene graph's instance ids, as the G-buffer names them.
        for (const Instance& i : to_scene_model(SceneGraph(scene).state()).instances)
            view.instances[i.id] = i.transform;
        view.gbuffer = test::first_hit_gbuffer(scene, view.camera, 0, kW, kH);
    }
    FloatImage frame(uint32_t k, int spp) const {
        test::RenderRequest r;
        r.width = kW;
        r.height = kH;
        r.spp = spp;
        r.frame = k;
        r.seed = 11;
        return test::render(scene, r);
    }
};

const Still& still() {
    static const Still s;
    return s;
}

const FloatImage& reference() {
    static const FloatImage r = still().frame(100000, 1024);
    return r;
}

TEST(Denoiser, LeavesAConvergedImageWithinOnePercent) {
    FloatImage single = reference();
    denoise_frame(single, still().view.gbuffer, still().view.camera);
    EXPECT_LT(relative_mse(single, reference()), 0.01) << "one frame, spatial variance";
    Denoiser temporal;
    FloatImage out;
    for (int k = 0; k < 8; ++k) {
        out = reference();
        temporal.filter(out, still().view, true);
    }
    EXPECT_LT(relative_mse(out, reference()), 0.01) << "eight frames, temporal variance";
}

// One frame alone (pathfarm-render --denoise): at least 4x less error at 1 spp, 2.5x at 4.
TEST(Denoiser, CutsTheErrorOfOneNoisyFrame) {
    for (const auto& [spp, factor] : {std::pair{1, 0.25}, std::pair{4, 0.4}}) {
        const FloatImage raw = still().frame(1, spp);
        FloatImage denoised = raw;
        denoise_frame(denoised, still().view.gbuffer, still().view.camera);
        const double before = relative_mse(raw, reference()),
                     after = relative_mse(denoised, reference());
        EXPECT_LT(after, factor * before) << spp << " spp: " << before << " -> " << after;
    }
}

// A still view at 1 spp a frame, the denoised sequence against converging alone: never worse,
// and half the error or less over the 16 frames (a firefly in frame 3 costs both).
TEST(Denoiser, BeatsConvergingAloneOnAStillView) {
    Denoiser denoiser;
    TemporalAccumulator accumulator;
    double denoised_sum = 0.0, converged_sum = 0.0;
    for (int k = 1; k <= 16; ++k) {
        const FloatImage raw = still().frame(uint32_t(k), 1);
        FloatImage denoised = raw, converged = raw;
        denoiser.filter(denoised, still().view, true);
        accumulator.blend(converged, still().view);
        // What the farm shows again for a frame it does not render.
        EXPECT_EQ(denoiser.output().rgb, denoised.rgb) << "frame " << k;
        EXPECT_EQ(accumulator.output().rgb, converged.rgb) << "frame " << k;
        const double d = relative_mse(denoised, reference()),
                     c = relative_mse(converged, reference());
        EXPECT_LT(d, c) << "frame " << k;
        denoised_sum += d;
        converged_sum += c;
    }
    EXPECT_LT(denoised_sum, 0.5 * converged_sum) << denoised_sum << " against " << converged_sum;
    const FloatImage last = denoiser.output();
    denoiser.reset();  // a cut: the history goes, the last output stays until the next frame
    EXPECT_EQ(denoiser.output().rgb, last.rgb);
}

}  // namespace
}  // namespace pathfarm::coord::denoiser_test
