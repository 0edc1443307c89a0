// The denoiser on what a mirror shows: builtin:default's wall mirror seen from random places in
// the room. Its first hits are the surfaces the mirror reflects (FirstHit::kReplaced), so the
// filter smooths their light over those surfaces, stopping at their edges. Before, the mirror's
// pixels were sharp and left as they came: a one-sample frame's noise.
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/scene/load/builtin_scenes.h"
#include "coordinator/converge/denoiser.h"
#include "tests/support/gbuffer_helpers.h"
#include "tests/support/render_helpers.h"

namespace pathfarm::coord::denoiser_mirror_test {
namespace {

constexpr int kW = 96, kH = 54;

// The mirror (common/scene/load/default_scene.cpp): the quad x = -3.98, y in [1.5, 2.4],
// z in [-3, -1.8], facing +x.
constexpr float kMirrorX = -3.98f, kMirrorY0 = 1.5f, kMirrorY1 = 2.4f, kMirrorZ0 = -3.0f,
                kMirrorZ1 = -1.8f;

// Pixels whose centre ray meets the mirror with nothing in front of it: the distance to the
// mirror along the ray, or a negative number.
std::vector<float> mirror_distances(const Camera& camera) {
    std::vector<float> out(std::size_t(kW) * kH, -1.0f);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const Ray r = generate_camera_ray(camera, kW, kH, x + 0.5f, y + 0.5f);
            const float t = (kMirrorX - r.o.x) / r.d.x;
            const Vec3 p = r.o + t * r.d;
            if (t > 0.0f && p.y > kMirrorY0 + 0.02f && p.y < kMirrorY1 - 0.02f &&
                p.z > kMirrorZ0 + 0.02f && p.z < kMirrorZ1 - 0.02f)
                out[std::size_t(y) * kW + x] = t;
        }
    return out;
}

// Relative MSE (image_compare.h's, eps 1e-2) over the pixels `mask` names.
double masked_relative_mse(const FloatImage& a, const FloatImage& reference,
                           const std::vector<uint8_t>& mask) {
    double sum = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (!mask[i]) continue;
        for (int c = 0; c < 3; ++c) {
            const double d = double(a.rgb[3 * i + c]) - reference.rgb[3 * i + c];
            sum += d * d / (double(reference.rgb[3 * i + c]) * reference.rgb[3 * i + c] + 1e-2);
        }
        ++n;
    }
    return n ? sum / (3.0 * n) : 0.0;
}

FloatImage render(const SceneModel& scene, uint32_t frame, int spp) {
    return test::render(scene, test::RenderRequest{.width = kW,
                                                   .height = kH,
                                                   .spp = spp,
                                                   .seed = 11,
                                                   .frame = frame,
                                                   .threads = 2,
                                                   .integrator = {},
                                                   .row_splits = {},
                                                   .backend = test::default_backend()});
}

float uniform(std::mt19937& rng, float lo, float hi) {
    return lo + (hi - lo) * float(rng() >> 8) * (1.0f / 16777216.0f);
}

// One frame of 1 sample a pixel, denoised alone (pathfarm-render --denoise): over the mirror's
// pixels at most 0.35x the raw frame's relative MSE against 128 samples a pixel. With the
// mirror's own first hits (sharp, unfiltered) the ratio is 1.
TEST(DenoiserMirror, WhatTheMirrorShowsIsFilteredOverTheSurfacesItReflects) {
    std::mt19937 rng(2026);
    for (int view = 0; view < 4; ++view) {
        SceneModel scene = make_default_scene();
        const Vec3 eye(uniform(rng, -2.8f, -1.8f), uniform(rng, 1.4f, 2.2f),
                       uniform(rng, -3.2f, -1.6f));
        const Vec3 at(kMirrorX, uniform(rng, 1.75f, 2.15f), uniform(rng, -2.6f, -2.2f));
        Camera camera;
        camera.camera_to_world = glm::inverse(glm::lookAt(eye, at, Vec3(0.0f, 1.0f, 0.0f)));
        camera.yfov_radians = glm::radians(40.0f);
        scene.cameras.at(0) = camera;
        const GBuffer g = test::first_hit_gbuffer(scene, camera, 0, kW, kH);
        const std::vector<float> mirror = mirror_distances(camera);
        std::vector<uint8_t> mask(mirror.size(), 0);
        int pixels = 0;
        for (std::size_t i = 0; i < mask.size(); ++i) {
            // Nothing in front of the mirror: the G-buffer's point lies on it or beyond.
            mask[i] = mirror[i] > 0.0f && g.distance[i] >= 0.999f * mirror[i];
            pixels += mask[i];
        }
        ASSERT_GT(pixels, kW * kH / 20) << "view " << view << ": the mirror fills the view";
        const FloatImage reference = render(scene, 100000, 128);
        const FloatImage raw = render(scene, 1, 1);
        FloatImage denoised = raw;
        denoise_frame(denoised, g, camera);
        const double before = masked_relative_mse(raw, reference, mask),
                     after = masked_relative_mse(denoised, reference, mask);
        EXPECT_LT(after, 0.35 * before)
            << "view " << view << ": " << pixels << " mirror pixels, relative MSE " << before
            << " -> " << after;
    }
}

}  // namespace
}  // namespace pathfarm::coord::denoiser_mirror_test
