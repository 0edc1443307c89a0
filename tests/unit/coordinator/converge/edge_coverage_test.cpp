// The far side of a silhouette (edge_coverage.h), searched over random scenes: a disc in front
// of a plane or the sky, at a random place, size, depth and colours, each pixel one jittered
// sample a frame (all disc or all background), against each pixel's true mix (its coverage by
// the disc, from 16x16 sub-samples). The denoiser with the step must cut the error of the far
// side's edge pixels and leave every other pixel as the denoiser without it leaves it; a still
// view with a long history keeps converging to its own samples.
#include <cmath>
#include <random>
#include <utility>

#include <gtest/gtest.h>

#include "common/film/image_compare.h"
#include "common/math/transform.h"
#include "coordinator/converge/denoiser.h"

namespace pathfarm::coord::edge_coverage_test {
namespace {

constexpr int kW = 48, kH = 36;

struct DiscScene {
    Camera camera;
    float disc_x = 0, disc_y = 0, radius = 0;  // in pixels
    float disc_depth = 0, back_depth = 0;      // back_depth: +inf for the sky
    Rgb disc_light, back_light;
    std::vector<float> coverage;  // per pixel, the disc's share

    bool in_disc(float px, float py) const {
        return (px - disc_x) * (px - disc_x) + (py - disc_y) * (py - disc_y) < radius * radius;
    }
    Rgb truth(std::size_t i) const {
        return coverage[i] * disc_light + (1.0f - coverage[i]) * back_light;
    }
};

DiscScene random_scene(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    DiscScene s;
    s.camera.camera_to_world = Mat4(1.0f);
    s.camera.yfov_radians = glm::radians(45.0f);
    s.disc_x = 12.0f + 24.0f * u(rng);
    s.disc_y = 10.0f + 16.0f * u(rng);
    s.radius = 2.0f + 8.0f * u(rng);
    s.disc_depth = 1.0f + 5.0f * u(rng);
    s.back_depth = u(rng) < 0.5f ? INFINITY : s.disc_depth * (1.5f + 4.0f * u(rng));
    const float bright = std::pow(10.0f, 2.0f * u(rng) - 1.0f);
    s.disc_light = bright * Rgb(0.3f + 0.7f * u(rng), 0.3f + 0.7f * u(rng), 0.3f + 0.7f * u(rng));
    s.back_light = (0.05f + 0.5f * u(rng)) * Rgb(u(rng), u(rng), u(rng));
    if (u(rng) < 0.5f) std::swap(s.disc_light, s.back_light);  // a dark object on bright
    s.coverage.resize(std::size_t(kW) * kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            int inside = 0;
            for (int j = 0; j < 16; ++j)
                for (int k = 0; k < 16; ++k)
                    inside += s.in_disc(x + (k + 0.5f) / 16.0f, y + (j + 0.5f) / 16.0f);
            s.coverage[std::size_t(y) * kW + x] = float(inside) / 256.0f;
        }
    return s;
}

// The centre hits: the disc (instance 2) or the background plane (1) or the sky (0).
FrameView view_of(const DiscScene& s) {
    FrameView v;
    v.camera = s.camera;
    v.gbuffer.resize(kW, kH);
    GBuffer& g = v.gbuffer;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const std::size_t i = std::size_t(y) * kW + x;
            const bool disc = s.in_disc(x + 0.5f, y + 0.5f);
            const float t = disc ? s.disc_depth : s.back_depth;
            if (!std::isfinite(t)) continue;  // the sky
            const Ray ray = generate_camera_ray(s.camera, kW, kH, x + 0.5f, y + 0.5f);
            const float along = t / -ray.d.z;  // planes facing the camera at depth t
            g.distance[i] = along;
            g.instance[i] = disc ? 2 : 1;
            g.position[i] = ray.o + along * ray.d;
            g.normal[i] = Vec3(0.0f, 0.0f, 1.0f);
            g.albedo[i] = Rgb(0.6f);
        }
    return v;
}

// One sample per pixel at a jittered point: all disc or all background.
FloatImage one_sample_frame(const DiscScene& s, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    FloatImage img(kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            img.set_pixel(x, y, s.in_disc(x + u(rng), y + u(rng)) ? s.disc_light : s.back_light);
    return img;
}

FloatImage truth_image(const DiscScene& s) {
    FloatImage img(kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            img.set_pixel(x, y, s.truth(std::size_t(y) * kW + x));
    return img;
}

double relative_error(const FloatImage& a, const FloatImage& truth, std::size_t i) {
    double sum = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double r = truth.rgb[3 * i + c], d = a.rgb[3 * i + c] - r;
        sum += d * d / (r * r + 1e-2);
    }
    return sum;
}

// Pixels whose centre sees the background with the disc's centre hits beside them (4-neighbours).
std::vector<uint8_t> far_side(const DiscScene& s) {
    std::vector<uint8_t> far(std::size_t(kW) * kH, 0);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            if (s.in_disc(x + 0.5f, y + 0.5f)) continue;
            for (const auto& [dx, dy] :
                 {std::pair{-1, 0}, std::pair{1, 0}, std::pair{0, -1}, std::pair{0, 1}})
                far[std::size_t(y) * kW + x] |= uint8_t(s.in_disc(x + dx + 0.5f, y + dy + 0.5f));
        }
    return far;
}

DenoiseOptions with_edges(bool on) {
    DenoiseOptions o;
    o.edges.model_frames = on ? EdgeCoverageOptions{}.model_frames : 0.0f;
    return o;
}

// The first frame of a view (no history): over 60 random scenes, the far side's edge pixels
// have at most half the relative error without the step, and no other pixel changes.
TEST(EdgeCoverage, FarSideOfASilhouetteTakesItsOwnLightNotTheObjects) {
    std::mt19937 rng(20261205);
    double with = 0.0, without = 0.0;
    int edge_pixels = 0;
    for (int trial = 0; trial < 60; ++trial) {
        const DiscScene s = random_scene(rng);
        const FloatImage frame = one_sample_frame(s, rng), truth = truth_image(s);
        FloatImage a = frame, b = frame;
        Denoiser on(with_edges(true)), off(with_edges(false));
        on.filter(a, view_of(s), true);
        off.filter(b, view_of(s), true);
        const std::vector<uint8_t> on_far_side = far_side(s);
        for (std::size_t i = 0; i < on_far_side.size(); ++i) {
            if (!on_far_side[i]) {
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ(a.rgb[3 * i + c], b.rgb[3 * i + c]) << "trial " << trial;
                continue;
            }
            with += relative_error(a, truth, i);
            without += relative_error(b, truth, i);
            ++edge_pixels;
        }
    }
    ASSERT_GT(edge_pixels, 1000);
    EXPECT_LT(with, 0.5 * without) << "far-side edge pixels: " << edge_pixels;
}

// A still view whose frames are its true mixes (converged samples): after 32 frames the step
// has moved the far side's edge pixels by a mean relative error below 1e-4 (1e-5 here; 1.2e-3
// when the weight ignores the history), over 20 random scenes.
TEST(EdgeCoverage, AStillViewKeepsConvergingToItsOwnSamples) {
    std::mt19937 rng(5);
    double moved = 0.0;
    int pixels = 0;
    for (int trial = 0; trial < 20; ++trial) {
        const DiscScene s = random_scene(rng);
        const FloatImage truth = truth_image(s);
        Denoiser on(with_edges(true)), off(with_edges(false));
        FloatImage a, b;
        for (int k = 0; k < 32; ++k) {
            a = b = truth;
            on.filter(a, view_of(s), true);
            off.filter(b, view_of(s), true);
        }
        const std::vector<uint8_t> on_far_side = far_side(s);
        for (std::size_t i = 0; i < on_far_side.size(); ++i)
            if (on_far_side[i]) {
                moved += relative_error(a, b, i);
                ++pixels;
            }
    }
    EXPECT_LT(moved / pixels, 1e-4);
}

}  // namespace
}  // namespace pathfarm::coord::edge_coverage_test
