// How well the light tree chooses among builtin:light-field's 9 892 emitters (ceiling, upper
// walls, a ring and two-sided fireflies, six colours): at random receivers on the floor and the
// lower walls, the variance of a one-sample estimate of their unshadowed direct light, with
// emitters chosen by the tree against by power. The tree's bound alone chose almost as power
// does here (every group near the root surrounds the receivers); with the estimate beside it,
// it must do far better. Also: no emitter that lights a receiver has probability zero.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "common/render/light_sampler.h"
#include "common/render/shading_scene.h"
#include "common/scene/load/builtin_scenes.h"

namespace pathfarm {
namespace {

// Relative variance per sample, averaged over the colour channels, of choosing emitter k with
// probability pmf[k] and estimating the sum of f over all emitters as f[k] / pmf[k].
double relative_variance(const std::vector<Rgb>& f, const std::vector<double>& pmf) {
    double total = 0.0;
    for (int c = 0; c < 3; ++c) {
        double mean = 0.0, second = 0.0;
        for (std::size_t k = 0; k < f.size(); ++k) {
            const double fk = c == 0 ? f[k].r : c == 1 ? f[k].g : f[k].b;
            if (!(fk > 0.0)) continue;
            mean += fk;
            second += fk * fk / pmf[k];
        }
        total += (second - mean * mean) / (mean * mean) / 3.0;
    }
    return total;
}

TEST(LightTreeVariance, LightFieldReceiversGetFarLessVarianceThanByPower) {
    const SceneModel scene = make_light_field_scene();
    const ShadingScene shading(scene);
    const LightSampler tree(shading, {}, LightSelection::tree);
    const LightSampler power(shading, {}, LightSelection::power);
    const auto& emitters = tree.triangles();
    ASSERT_EQ(emitters.size(), power.triangles().size());
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u(-1.9f, 1.9f), height(0.05f, 1.5f);
    double ratio_sum = 0.0;
    const int receivers = 12;
    for (int i = 0; i < receivers; ++i) {
        // Even: the floor; odd: a lower wall facing into the room.
        const float side = (i / 2) % 2 ? 1.0f : -1.0f;
        const Vec3 p =
            i % 2 ? Vec3(-1.99f * side, height(rng), u(rng)) : Vec3(u(rng), 0.001f, u(rng));
        const Vec3 n = i % 2 ? Vec3(side, 0, 0) : Vec3(0, 1, 0);
        std::vector<Rgb> f(emitters.size());
        std::vector<double> by_tree(emitters.size()), by_power(emitters.size());
        for (std::size_t k = 0; k < emitters.size(); ++k) {
            const auto& e = emitters[k];
            const Vec3 d = e.p0 + (e.e1 + e.e2) / 3.0f - p;
            const float d2 = glm::dot(d, d);
            const Vec3 w = d / std::sqrt(d2);
            const Material& m = scene.materials[std::size_t(e.material)];
            const float out = m.double_sided ? std::abs(glm::dot(e.n, w)) : -glm::dot(e.n, w);
            const float in = glm::dot(n, w);
            f[k] = out > 0.0f && in > 0.0f ? m.emission() * (out * in / d2 * e.area) : Rgb(0.0f);
            by_tree[k] = tree.tree().pmf(p, n, uint32_t(k));
            by_power[k] = power.cdf()[k] - (k ? power.cdf()[k - 1] : 0.0f);
            if (max_component(f[k]) > 0.0f) {
                ASSERT_GT(by_tree[k], 0.0) << "emitter " << k << " lights receiver " << i;
            }
        }
        const double v_tree = relative_variance(f, by_tree),
                     v_power = relative_variance(f, by_power);
        std::printf("receiver %d: relative variance %.3f by tree, %.3f by power\n", i, v_tree,
                    v_power);
        EXPECT_LT(v_tree, 0.8 * v_power) << "receiver " << i;
        ratio_sum += v_tree / v_power;
    }
    EXPECT_LT(ratio_sum / receivers, 0.5) << "on average";
}

}  // namespace
}  // namespace pathfarm
