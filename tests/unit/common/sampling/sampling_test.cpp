// Warping functions: densities integrate to one and samples follow them (chi-square).
#include "common/sampling/sampling.h"

#include <gtest/gtest.h>

#include "common/math/frame.h"
#include "common/sampling/rng.h"
#include "tests/support/chi2.h"

namespace pathfarm {
namespace {

constexpr double kAlpha = 1e-3;  // per-test significance

TEST(Sampling, CosineHemisphereFollowsItsPdf) {
    const auto pdf = [](const Vec3& w) { return cosine_hemisphere_pdf(w.z); };
    EXPECT_NEAR(test::integrate_sphere(pdf), 1.0, 1e-3);
    const auto r = test::chi2_directions(
        [](float, Vec2 u, Vec3& w) {
            w = sample_cosine_hemisphere(u);
            return true;
        },
        pdf, 200000, 1);
    EXPECT_GT(r.p_value, kAlpha) << "chi2=" << r.statistic << " dof=" << r.dof;
}

TEST(Sampling, UniformSphereFollowsItsPdf) {
    const auto pdf = [](const Vec3&) { return kUniformSpherePdf; };
    EXPECT_NEAR(test::integrate_sphere(pdf), 1.0, 1e-3);
    const auto r = test::chi2_directions(
        [](float, Vec2 u, Vec3& w) {
            w = sample_uniform_sphere(u);
            return true;
        },
        pdf, 200000, 2);
    EXPECT_GT(r.p_value, kAlpha) << "chi2=" << r.statistic;
}

TEST(Sampling, ConeFollowsItsPdf) {
    const float cos_max = 2.0f / 3.0f;  // on a bin boundary: the numerical integral is exact
    const auto pdf = [&](const Vec3& w) {
        return w.z >= cos_max ? uniform_cone_pdf(cos_max) : 0.0f;
    };
    EXPECT_NEAR(test::integrate_sphere(pdf, 1000), 1.0, 2e-2);
    const auto r = test::chi2_directions(
        [&](float, Vec2 u, Vec3& w) {
            w = sample_uniform_cone(u, cos_max);
            return true;
        },
        pdf, 200000, 3);
    EXPECT_GT(r.p_value, kAlpha) << "chi2=" << r.statistic;
}

TEST(Sampling, TriangleSamplesAreUniformByArea) {
    // Count samples in the 4 sub-triangles of a midpoint subdivision: each has a quarter of the
    // area.
    Pcg32 rng(4);
    int counts[4] = {0, 0, 0, 0};
    constexpr int kN = 100000;
    for (int i = 0; i < kN; ++i) {
        const Vec2 b = sample_uniform_triangle(rng.next_2d());
        ASSERT_GE(b.x, 0.0f);
        ASSERT_GE(b.y, 0.0f);
        ASSERT_LE(b.x + b.y, 1.0f + 1e-6f);
        const float b0 = 1.0f - b.x - b.y;
        counts[b0 > 0.5f ? 0 : b.x > 0.5f ? 1 : b.y > 0.5f ? 2 : 3]++;
    }
    double chi2 = 0.0;
    for (int c : counts)
        chi2 += (c - kN / 4.0) * (c - kN / 4.0) / (kN / 4.0);
    EXPECT_GT(test::chi2_p_value(chi2, 3), kAlpha) << chi2;
}

TEST(Sampling, PowerHeuristicIsAPartitionOfUnity) {
    for (float a : {0.0f, 0.1f, 1.0f, 7.0f})
        for (float b : {0.1f, 1.0f, 30.0f})
            EXPECT_NEAR(power_heuristic(a, b) + power_heuristic(b, a), 1.0f, 1e-6f);
    EXPECT_EQ(power_heuristic(kInfinity, 1.0f), 1.0f);
}

TEST(Frame, IsOrthonormalForAnyNormal) {
    Pcg32 rng(5);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 n = sample_uniform_sphere(rng.next_2d());
        const Frame f = Frame::from_normal(n);
        EXPECT_NEAR(glm::dot(f.t, f.b), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(f.t, n), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::length(f.t), 1.0f, 1e-5f);
        const Vec3 v = sample_uniform_sphere(rng.next_2d());
        EXPECT_NEAR(glm::distance(f.to_world(f.to_local(v)), v), 0.0f, 1e-5f);
    }
}

}  // namespace
}  // namespace pathfarm
