// The sun/sky as a light (audit after the tilted-light bias): next-event estimation divides by
// SunSky::pdf, so the directions sample() draws must follow that density. The sun is a
// 0.5-degree cone, far too small for a histogram test, so the check is the estimator NEE uses:
// the mean of L(w) cos / pdf(w) over sampled directions equals the irradiance integrated by
// quadrature (the sky on a fine grid, the sun's cone analytically), for several suns and
// normals. And wherever radiance is non-zero the density is too (no direction unreachable).
#include <random>

#include <gtest/gtest.h>

#include "common/math/frame.h"
#include "common/render/sun_sky.h"
#include "common/sampling/sampling.h"

namespace pathfarm {
namespace {

struct Setting {
    Vec3 sun;
    Vec3 normal;
};

double irradiance_by_quadrature(const SunSky& sky, const Vec3& n) {
    // The sky over a fine (cos theta, phi) grid of the upper hemisphere, the sun cone excluded.
    constexpr int kTheta = 600, kPhi = 1200;
    const double cell = (1.0 / kTheta) * (2.0 * kPi / kPhi);
    const float cos_sun = std::cos(kSunHalfAngleRadians);
    double e = 0.0;
    for (int i = 0; i < kTheta; ++i) {
        const float cos_t = (float(i) + 0.5f) / float(kTheta);
        const float sin_t = std::sqrt(1.0f - cos_t * cos_t);
        for (int j = 0; j < kPhi; ++j) {
            const float phi = 2.0f * kPi * (float(j) + 0.5f) / float(kPhi);
            const Vec3 w(sin_t * std::cos(phi), cos_t, sin_t * std::sin(phi));
            if (glm::dot(w, sky.sun_direction()) >= cos_sun) continue;
            e += double(luminance(sky.radiance(w))) * std::max(0.0f, glm::dot(w, n)) * cell;
        }
    }
    // The sun's cone on a polar grid of its own (a sun at the normal's horizon is half
    // above it): its radiance is the sun colour times kSunIrradiance per cone solid angle.
    const Frame sun = Frame::from_normal(sky.sun_direction());
    const double cone = 2.0 * kPi * (1.0 - double(cos_sun));
    const double sun_luminance = kSunIrradiance * double(luminance(Rgb(1.0f, 0.93f, 0.82f))) / cone;
    constexpr int kRings = 200, kSectors = 400;
    for (int i = 0; i < kRings; ++i) {
        const float cos_a = 1.0f - (1.0f - cos_sun) * (float(i) + 0.5f) / float(kRings);
        const float sin_a = std::sqrt(std::max(0.0f, 1.0f - cos_a * cos_a));
        for (int j = 0; j < kSectors; ++j) {
            const float phi = 2.0f * kPi * (float(j) + 0.5f) / float(kSectors);
            const Vec3 w = sun.to_world(Vec3(sin_a * std::cos(phi), sin_a * std::sin(phi), cos_a));
            e += sun_luminance * std::max(0.0f, glm::dot(w, n)) * cone / (kRings * kSectors);
        }
    }
    return e;
}

double irradiance_by_sampling(const SunSky& sky, const Vec3& n, uint32_t seed) {
    std::mt19937 rng(seed);
    const auto u = [&] { return float(rng() >> 8) * 0x1p-24f; };
    constexpr int kSamples = 1 << 21;
    double e = 0.0;
    for (int k = 0; k < kSamples; ++k) {
        const EnvSample s = sky.sample(u(), Vec2(u(), u()));
        if (s.pdf <= 0.0f) continue;
        EXPECT_FLOAT_EQ(s.pdf, sky.pdf(s.wi));
        e += double(luminance(s.radiance)) * std::max(0.0f, glm::dot(s.wi, n)) / s.pdf;
    }
    return e / kSamples;
}

TEST(SunSky, NextEventEstimateOfIrradianceMatchesQuadrature) {
    const Setting settings[] = {
        {glm::normalize(Vec3(0.35f, 0.8f, 0.45f)), Vec3(0, 1, 0)},
        {glm::normalize(Vec3(-0.6f, 0.3f, 0.2f)), glm::normalize(Vec3(-0.5f, 0.5f, 0.1f))},
        {glm::normalize(Vec3(0.1f, 0.12f, -0.9f)), glm::normalize(Vec3(0.3f, 0.2f, -0.9f))},
        {glm::normalize(Vec3(0.0f, 1.0f, 0.05f)), glm::normalize(Vec3(1.0f, 0.0f, 0.0f))},
    };
    uint32_t seed = 1;
    for (const Setting& s : settings) {
        Environment env;
        env.sun_direction = s.sun;
        const SunSky sky(env);
        const double quad = irradiance_by_quadrature(sky, s.normal);
        const double mc = irradiance_by_sampling(sky, s.normal, seed++);
        EXPECT_NEAR(mc / quad, 1.0, 0.01)
            << "sun " << s.sun.x << "," << s.sun.y << "," << s.sun.z << " normal " << s.normal.x
            << "," << s.normal.y << "," << s.normal.z << ": " << mc << " vs " << quad;
    }
}

TEST(SunSky, DensityIsPositiveWhereverRadianceIs) {
    Environment env;
    env.sun_direction = glm::normalize(Vec3(0.2f, 0.5f, -0.7f));
    const SunSky sky(env);
    std::mt19937 rng(7);
    const auto u = [&] { return float(rng() >> 8) * 0x1p-24f; };
    for (int k = 0; k < 200000; ++k) {
        Vec3 w = sample_uniform_sphere(Vec2(u(), u()));
        if (k % 2)
            w = Frame::from_normal(sky.sun_direction())
                    .to_world(
                        sample_uniform_cone(Vec2(u(), u()), std::cos(2.0f * kSunHalfAngleRadians)));
        if (max_component(sky.radiance(w)) > 0.0f) {
            ASSERT_GT(sky.pdf(w), 0.0f) << k;
        }
    }
}

}  // namespace
}  // namespace pathfarm
