// The glTF BSDF: its sampler follows its pdf (chi-square), densities integrate to at most one,
// reflection is reciprocal, and no material reflects more energy than it receives.
#include "common/render/bsdf.h"

#include <gtest/gtest.h>

#include "common/sampling/rng.h"
#include "common/sampling/sampling.h"
#include "tests/support/chi2.h"

namespace pathfarm {
namespace {

struct Case {
    const char* name;
    MaterialPoint mp;
};

MaterialPoint mat(Rgb base, float metallic, float roughness, float transmission = 0.0f,
                  float specular = 1.0f) {
    MaterialPoint mp;
    mp.base_color = base;
    mp.metallic = metallic;
    mp.alpha = roughness * roughness;
    mp.transmission = transmission;
    mp.specular = specular;
    return mp;
}

std::vector<Case> rough_cases() {
    return {{"lambert", mat(Rgb(0.8f), 0, 1, 0, 0)},
            {"plastic_rough", mat(Rgb(0.5f, 0.2f, 0.1f), 0, 0.7f)},
            {"plastic_glossy", mat(Rgb(0.2f, 0.6f, 0.3f), 0, 0.45f)},
            {"metal_rough", mat(Rgb(0.9f, 0.7f, 0.3f), 1, 0.6f)},
            {"metal_glossy", mat(Rgb(0.95f), 1, 0.45f)},
            {"half_metal", mat(Rgb(0.6f), 0.5f, 0.55f)},
            {"rough_glass", mat(Rgb(1.0f), 0, 0.5f, 1.0f)},
            {"mixed_glass", mat(Rgb(0.7f), 0, 0.6f, 0.5f)}};
}

const Vec3 kOutgoing[] = {glm::normalize(Vec3(0.3f, 0.2f, 0.9f)),
                          glm::normalize(Vec3(-0.8f, 0.1f, 0.35f)),
                          glm::normalize(Vec3(0.1f, -0.9f, 0.12f))};

TEST(Bsdf, SamplesFollowPdf) {
    uint64_t seed = 10;
    for (const Case& c : rough_cases()) {
        const Bsdf bsdf(c.mp);
        for (Vec3 wo : kOutgoing) {
            for (float side : {1.0f, -1.0f}) {
                if (side < 0.0f && !bsdf.transmissive()) continue;
                const Vec3 w = Vec3(wo.x, wo.y, side * wo.z);
                const auto r = test::chi2_directions(
                    [&](float ul, Vec2 u, Vec3& wi) {
                        BsdfSample s;
                        if (!bsdf.sample(w, ul, u, s)) return false;
                        wi = s.wi;
                        return true;
                    },
                    [&](const Vec3& wi) { return bsdf.pdf(w, wi); }, 300000, ++seed);
                EXPECT_GT(r.p_value, 1e-4)
                    << c.name << " wo.z=" << w.z << " chi2=" << r.statistic << " dof=" << r.dof;
            }
        }
    }
}

TEST(Bsdf, PdfIntegratesToAtMostOne) {
    for (const Case& c : rough_cases()) {
        const Bsdf bsdf(c.mp);
        for (Vec3 wo : kOutgoing) {
            const double integral =
                test::integrate_sphere([&](const Vec3& wi) { return bsdf.pdf(wo, wi); }, 600);
            EXPECT_LE(integral, 1.02) << c.name;
            EXPECT_GT(integral, 0.5) << c.name;
        }
    }
}

TEST(Bsdf, ReflectionIsReciprocal) {
    Pcg32 rng(3);
    for (const Case& c : rough_cases()) {
        const Bsdf bsdf(c.mp);
        for (int i = 0; i < 200; ++i) {
            const Vec3 a = sample_cosine_hemisphere(rng.next_2d());
            const Vec3 b = sample_cosine_hemisphere(rng.next_2d());
            const Rgb fab = bsdf.eval(a, b), fba = bsdf.eval(b, a);
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(fab[k], fba[k], 1e-4f * (1.0f + fab[k])) << c.name;
        }
    }
}

// Albedo = E[f cos / pdf] over the BSDF's own samples (delta lobes included) must not exceed 1.
Rgb albedo(const Bsdf& bsdf, const Vec3& wo, int n, uint64_t seed) {
    Pcg32 rng(seed);
    glm::dvec3 sum(0.0);
    for (int i = 0; i < n; ++i) {
        BsdfSample s;
        if (!bsdf.sample(wo, rng.next_float(), rng.next_2d(), s) || s.pdf <= 0.0f) continue;
        sum += glm::dvec3(s.f * std::abs(s.wi.z) / s.pdf);
    }
    return Rgb(sum / double(n));
}

TEST(Bsdf, ConservesEnergy) {
    std::vector<Case> cases = rough_cases();
    cases.push_back({"white_metal_smooth", mat(Rgb(1.0f), 1, 0)});
    cases.push_back({"white_plastic_smooth", mat(Rgb(1.0f), 0, 0)});
    cases.push_back({"white_plastic_rough", mat(Rgb(1.0f), 0, 0.3f)});
    cases.push_back({"smooth_glass", mat(Rgb(1.0f), 0, 0, 1)});
    for (const Case& c : cases) {
        const Bsdf bsdf(c.mp);
        for (Vec3 wo : kOutgoing) {
            const Rgb a = albedo(bsdf, wo, 100000, 17);
            // Glass may exceed 1 by the 1/eta^2 radiance scaling when leaving the medium, never
            // when entering; from outside (wo.z > 0) it must conserve.
            EXPECT_LE(max_component(a), 1.01f) << c.name << " wo.z=" << wo.z;
        }
    }
}

TEST(Bsdf, WhiteLambertReflectsEverything) {
    const Bsdf bsdf(mat(Rgb(1.0f), 0, 1, 0, 0));
    const Rgb a = albedo(bsdf, kOutgoing[0], 20000, 5);
    EXPECT_NEAR(a.x, 1.0f, 1e-3f);
}

TEST(Bsdf, SmoothGlassSplitsByFresnel) {
    const Bsdf bsdf(mat(Rgb(1.0f), 0, 0, 1));
    const Vec3 wo(0, 0, 1);
    int reflected = 0;
    constexpr int kN = 20000;
    Pcg32 rng(8);
    for (int i = 0; i < kN; ++i) {
        BsdfSample s;
        ASSERT_TRUE(bsdf.sample(wo, rng.next_float(), rng.next_2d(), s));
        EXPECT_TRUE(s.delta);
        reflected += s.wi.z > 0.0f;
    }
    EXPECT_NEAR(double(reflected) / kN, 0.04, 0.006);  // ((1.5-1)/(1.5+1))^2 at normal incidence
}

}  // namespace
}  // namespace pathfarm
