// The light tree's estimate of a group's light (light_bounds.h) against the exact sum over its
// emitters, for random groups seen from afar (where the estimate's point approximation of
// distance and receiver cosine is exact, so what is left is how it models the emitters'
// orientations): a fraction q of the power facing one random way, the rest facing random
// directions (a ring of lights facing out, fireflies), some two-sided. The mean normal alone
// says the randomly facing part emits almost nothing; it lights every direction a quarter of
// its power on average, and an estimate that misses it starves such groups of samples.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "common/render/light_bounds.h"
#include "tests/support/random_geometry.h"

namespace pathfarm::light_estimate_test {
namespace {

using test::random_direction;

struct Group {
    std::vector<Vec3> normals;
    std::vector<float> powers;
    std::vector<bool> two_sided;
    LightBounds bounds;
};

// `count` tiny triangles within 0.01 of the origin.
Group random_group(std::mt19937& rng, int count) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float aligned_share = u(rng) < 0.25f ? 0.0f : u(rng);
    const float two_sided_share = u(rng) < 0.5f ? 0.0f : 0.5f * u(rng);
    const Vec3 axis = random_direction(rng);
    Group g;
    for (int i = 0; i < count; ++i) {
        // Two-sided emitters face random ways (fireflies): the estimate counts half their power
        // in every direction, which is their mean |cos|.
        const bool two = u(rng) < two_sided_share;
        const Vec3 n = !two && u(rng) < aligned_share ? axis : random_direction(rng);
        const Vec3 t = glm::normalize(glm::cross(n, random_direction(rng)));
        const Vec3 c = 0.01f * Vec3(u(rng), u(rng), u(rng));
        const float power = 0.5f + u(rng);
        const LightBounds b =
            triangle_light_bounds(c, c + 1e-3f * t, c + 1e-3f * glm::cross(n, t), n, power, two);
        g.bounds = i == 0 ? b : union_bounds(g.bounds, b);
        g.normals.push_back(n);
        g.powers.push_back(power);
        g.two_sided.push_back(two);
    }
    return g;
}

TEST(LightEstimate, RandomlyFacingEmittersAreEstimatedWithinAFewPercentOfTheirLight) {
    std::mt19937 rng(17);
    for (int i = 0; i < 200; ++i) {
        const Group g = random_group(rng, 2000);
        const PackedLightBounds packed = pack(g.bounds);
        for (int j = 0; j < 8; ++j) {
            const Vec3 w = random_direction(rng);  // from the group towards the receiver
            const Vec3 p = 100.0f * w;
            const Vec3 n = -w;  // facing the group: a receiver cosine of one
            double exact = 0.0;
            for (std::size_t k = 0; k < g.normals.size(); ++k) {
                const float c = glm::dot(g.normals[k], w);
                exact += g.powers[k] * (g.two_sided[k] ? std::abs(c) : std::max(0.0f, c));
            }
            exact /= double(glm::dot(p, p));
            const float estimated = estimate(packed, p, n, false);
            // Sampling noise of 2 000 random normals is about 1 % of the total power.
            const double total = double(g.bounds.power) / double(glm::dot(p, p));
            EXPECT_NEAR(estimated, exact, 0.05 * exact + 0.02 * total)
                << "group " << i << " direction " << j;
        }
    }
}

}  // namespace
}  // namespace pathfarm::light_estimate_test
