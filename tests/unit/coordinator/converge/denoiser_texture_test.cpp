// The denoiser on a surface whose texture changes within a pixel: the Cornell box with its back
// wall in fine white and blue stripes (a pixel's jittered samples see both colours, its centre
// hit one). Demodulating by the centre's base colour alone blew the light of such pixels up
// (white samples divided by blue: 16 times too much red) and the filter spread it; divided by
// the base colour over the pixel's footprint, a noisy frame comes out closer to the reference.
#include <gtest/gtest.h>

#include "common/film/image_compare.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/scene_state.h"
#include "coordinator/converge/denoiser.h"
#include "coordinator/scene_graph/scene_graph.h"
#include "tests/support/gbuffer_helpers.h"
#include "tests/support/render_helpers.h"

namespace pathfarm::coord::denoiser_texture_test {
namespace {

constexpr int kW = 64, kH = 64;

// Vertical stripes, `stripes` pairs across, white and saturated blue, sampled nearest.
SceneModel striped_cornell(int stripes) {
    SceneModel scene = make_cornell_box();
    Image img;
    img.name = "stripes";
    img.width = 2 * stripes;
    img.height = 1;
    for (int x = 0; x < img.width; ++x) {
        const bool white = x % 2 == 0;
        for (const uint8_t c : {white ? 230 : 10, white ? 230 : 25, white ? 230 : 200, 255})
            img.rgba.push_back(c);
    }
    scene.images.push_back(img);
    Sampler sampler;
    sampler.filter = FilterMode::nearest;
    scene.textures.push_back(Texture{int(scene.images.size()) - 1, sampler});
    Material wall = scene.materials.at(std::size_t(scene.meshes.at(2).material));
    wall.name = "striped";
    wall.base_color_factor = Vec4(1.0f);
    wall.base_color_texture.texture = int(scene.textures.size()) - 1;
    scene.materials.push_back(wall);
    scene.meshes.at(2).material = int(scene.materials.size()) - 1;  // the back wall
    return scene;
}

FloatImage render(const SceneModel& scene, uint32_t k, int spp) {
    return test::render(scene, test::RenderRequest{.width = kW,
                                                   .height = kH,
                                                   .spp = spp,
                                                   .seed = 5,
                                                   .frame = k,
                                                   .threads = 2,
                                                   .integrator = {},
                                                   .row_splits = {},
                                                   .backend = test::default_backend()});
}

// 16 and 24 stripe pairs across the wall: periods of about 2.4 and 1.6 pixels. With the
// centre's base colour the 24-stripe wall came out at 0.27x (1 spp) and 1.6x (4 spp: worse than
// the raw frame) of the raw frame's error; with the footprint's at 0.15x and 0.68x.
TEST(DenoiserTextures, StripesNarrowerThanTwoPixelsDoNotBlowTheLightUp) {
    for (const int stripes : {16, 24}) {
        const SceneModel scene = striped_cornell(stripes);
        const Camera& camera = scene.cameras.at(0);
        const GBuffer g = test::first_hit_gbuffer(scene, camera, 0, kW, kH);
        const FloatImage reference = render(scene, 100000, 1024);
        for (const auto& [spp, factor] : {std::pair{1, 0.2}, std::pair{4, 0.75}}) {
            const FloatImage raw = render(scene, 1, spp);
            FloatImage denoised = raw;
            denoise_frame(denoised, g, camera);
            const double before = relative_mse(raw, reference),
                         after = relative_mse(denoised, reference);
            EXPECT_LT(after, factor * before)
                << stripes << " stripes, " << spp << " spp: " << before << " -> " << after;
        }
    }
}

}  // namespace
}  // namespace pathfarm::coord::denoiser_texture_test
