// The wavelet's row pass is built three times (16 lanes on x86-64-v4, 8 on x86-64-v3, 8 in SSE
// quarters on the baseline) and the CPU picks one, so a machine runs only one of them unless a
// test asks. Every set this CPU runs must give the baseline's image up to float rounding, on
// random G-buffers of widths that are not multiples of any lane count (the rows' tails).
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/math/transform.h"
#include "coordinator/converge/atrous.h"
#include "coordinator/converge/denoiser.h"

namespace pathfarm::coord::atrous_isa_test {
namespace {

struct Scene {
    GBuffer g;
    FloatImage image;
    Camera camera;
};

// Surfaces at random depths and orientations in blocks (so taps meet both edges and plain
// stretches), some sky, some sharp pixels, light with noise.
Scene random_scene(int w, int h, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Scene s;
    s.camera.camera_to_world = Mat4(1.0f);
    s.camera.yfov_radians = glm::radians(40.0f + 30.0f * u(rng));
    s.g.resize(w, h);
    s.image = FloatImage(w, h);
    const int block = 3 + int(u(rng) * 12.0f);
    std::vector<Vec3> normals;
    std::vector<float> depths, light;
    for (int b = 0; b < 64; ++b) {
        normals.push_back(glm::normalize(Vec3(u(rng) - 0.5f, u(rng) - 0.5f, 0.3f + u(rng))));
        depths.push_back(0.5f + 50.0f * u(rng));
        light.push_back(std::pow(10.0f, -1.0f + 3.0f * u(rng)));
    }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            const std::size_t b = std::size_t((y / block) * 8 + (x / block) % 8) % normals.size();
            const float noise = 0.2f + 1.6f * u(rng);
            for (int c = 0; c < 3; ++c)
                s.image.rgb[3 * i + c] = light[b] * noise * (0.5f + 0.5f * u(rng));
            if (u(rng) < 0.05f) continue;  // the sky
            const Ray ray = generate_camera_ray(s.camera, w, h, x + 0.5f, y + 0.5f);
            s.g.distance[i] = depths[b];
            s.g.instance[i] = uint32_t(1 + b);
            s.g.position[i] = ray.o + depths[b] * ray.d;
            s.g.normal[i] = normals[b];
            s.g.albedo[i] = Rgb(0.2f + 0.8f * u(rng), 0.2f + 0.8f * u(rng), 0.2f + 0.8f * u(rng));
            s.g.sharp[i] = u(rng) < 0.02f;
        }
    return s;
}

FloatImage denoised(const Scene& s, AtrousIsa isa, int radius) {
    EXPECT_TRUE(use_atrous_isa(isa));
    DenoiseOptions options;
    options.atrous.radius = radius;
    FloatImage out = s.image;
    denoise_frame(out, s.g, s.camera, options);
    return out;
}

// Largest difference relative to the pixel's value (plus a floor for near-black pixels).
double largest_relative_difference(const FloatImage& a, const FloatImage& b) {
    double worst = 0.0;
    for (std::size_t j = 0; j < a.rgb.size(); ++j)
        worst = std::max(
            worst, std::abs(double(a.rgb[j]) - b.rgb[j]) / (std::abs(double(b.rgb[j])) + 1e-3));
    return worst;
}

TEST(AtrousIsa, EverySetTheCpuRunsGivesTheBaselinesImage) {
    const AtrousIsa best = atrous_isa();
    std::vector<AtrousIsa> others;
    for (const AtrousIsa isa : {AtrousIsa::kX86_64_V3, AtrousIsa::kX86_64_V4})
        if (int(isa) <= int(best)) others.push_back(isa);
    // x86-64 machines without AVX2 (before 2013) would compare nothing here.
    ASSERT_FALSE(others.empty()) << "this CPU runs only the baseline row pass";
    std::mt19937 rng(20261204);
    std::uniform_int_distribution<int> size(17, 90);
    for (int trial = 0; trial < 12; ++trial) {
        const int w = size(rng) | 1, h = size(rng) / 2 + 3;  // odd widths: every row has a tail
        const Scene s = random_scene(w, h, rng);
        for (const int radius : {1, 2}) {
            const FloatImage reference = denoised(s, AtrousIsa::kBaseline, radius);
            for (const AtrousIsa isa : others) {
                const FloatImage out = denoised(s, isa, radius);
                // FMA contraction on v3 and v4 rounds differently from the baseline; a wrong
                // tap, lane or tail is off by far more.
                EXPECT_LT(largest_relative_difference(out, reference), 1e-3)
                    << "trial " << trial << " " << w << "x" << h << " radius " << radius << " isa "
                    << int(isa);
            }
        }
    }
    use_atrous_isa(best);
}

}  // namespace
}  // namespace pathfarm::coord::atrous_isa_test
