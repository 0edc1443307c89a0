// --light-sampler auto (light_sampler_choice.cpp): it chooses as measured on the built-in
// scenes, its reading from a few of the tree's choices per receiver agrees with the whole sum
// over every emitter on random scenes, and the sampler it resolves to is that sampler exactly.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "common/render/light_sampler.h"
#include "common/render/shading_scene.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_builder.h"

namespace pathfarm {
namespace {

LightChoice choice_for(const SceneModel& scene) {
    const ShadingScene shading(scene);
    const LightSampler lights(shading, {}, LightSelection::automatic);
    EXPECT_NE(lights.selection(), LightSelection::automatic);
    EXPECT_EQ(lights.requested(), LightSelection::automatic);
    EXPECT_EQ(lights.tree().empty(), lights.selection() == LightSelection::power);
    return lights.choice();
}

// The scenes whose time at equal error docs/performance.md measured: the tree takes 1.6-1.8x
// power's on the furnace and 0.21-0.67x on the others; one quad light renders the same image
// either way, so power skips the tree's work.
TEST(LightSamplerChoice, ChoosesAsMeasuredOnTheBuiltinScenes) {
    struct Case {
        const char* name;
        SceneModel scene;
        LightSelection expected;
    };
    const Case cases[] = {
        {"furnace", make_furnace_scene(), LightSelection::power},
        {"cornell", make_cornell_box(), LightSelection::power},
        {"many-lights", make_many_lights_scene(), LightSelection::tree},
        {"light-field", make_light_field_scene(), LightSelection::tree},
        {"default", make_default_scene(), LightSelection::tree},
        {"sealed-lights", make_sealed_lights_scene(), LightSelection::tree},
    };
    for (const Case& c : cases) {
        const LightChoice choice = choice_for(c.scene);
        std::printf("%s: %s, tree's variance %.3fx power's over %d receivers%s\n", c.name,
                    light_selection_name(choice.selection), choice.variance_ratio, choice.receivers,
                    choice.first_look ? " (first look)" : "");
        EXPECT_EQ(choice.selection, c.expected) << c.name << ": ratio " << choice.variance_ratio;
        EXPECT_GE(choice.receivers, LightChoice::kFirstLook / 2) << c.name;
    }
}

TEST(LightSamplerChoice, ASceneWithoutEmittersChoosesPowerWithoutReading) {
    SceneBuilder b("dark");
    const int grey = b.add_material(make_lambert("grey", Rgb(0.5f)));
    b.add_instance(b.add_mesh(make_unit_cube(grey)), Mat4(1.0f));
    const LightChoice choice = choice_for(b.finish());
    EXPECT_EQ(choice.selection, LightSelection::power);
    EXPECT_EQ(choice.receivers, 0);
}

// The resolved sampler is the chosen one to the bit (what a tracer asked for tree or power
// renders), and the choice is a function of the state: the same with a warm topology cache.
TEST(LightSamplerChoice, ResolvesToExactlyTheChosenSampler) {
    for (const SceneModel& scene : {make_furnace_scene(), make_light_field_scene()}) {
        const ShadingScene shading(scene);
        LightTopologyCache cache;
        const LightSampler cold(shading, {}, LightSelection::automatic, &cache);
        const LightSampler warm(shading, {}, LightSelection::automatic, &cache);
        EXPECT_EQ(cold.choice().variance_ratio, warm.choice().variance_ratio);
        const LightSampler same(shading, {}, cold.selection());
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(0.0f, 1.0f), x(-2.0f, 2.0f);
        for (int i = 0; i < 2000; ++i) {
            const Vec3 p(x(rng), x(rng) + 2.0f, x(rng)),
                n = glm::normalize(Vec3(x(rng), 1, x(rng)));
            const float us = u(rng);
            const Vec2 uv(u(rng), u(rng));
            const auto a = warm.sample(p, n, us, uv), b = same.sample(p, n, us, uv);
            ASSERT_EQ(a.has_value(), b.has_value());
            if (!a) continue;
            ASSERT_EQ(a->pdf, b->pdf) << "query " << i;
            ASSERT_EQ(a->p, b->p) << "query " << i;
        }
    }
}

// A random scene: a floor and walls, and emitters of a few materials (one- and two-sided,
// radiances over three decades), scattered as small quads, an emitting enclosure round the room,
// or both.
SceneModel random_scene(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    SceneBuilder b("random");
    const int grey = b.add_material(make_lambert("grey", Rgb(0.6f)));
    b.add_instance(b.add_mesh(make_quad(Vec3(0), Vec3(4, 0, 0), Vec3(0, 0, -4), grey)), Mat4(1));
    b.add_instance(b.add_mesh(make_quad(Vec3(-4, 2, 0), Vec3(0, 0, -4), Vec3(0, 2, 0), grey)),
                   Mat4(1));
    std::vector<int> lamps;
    for (int m = 0; m < 4; ++m) {
        const float scale = std::pow(10.0f, 3.0f * u(rng) - 1.0f);
        lamps.push_back(b.add_material(make_emitter(
            "lamp", Rgb(u(rng) + 0.1f, u(rng) + 0.1f, u(rng) + 0.1f) * scale, u(rng) < 0.3f)));
    }
    const int kind = int(u(rng) * 3.0f);
    if (kind != 1) {  // scattered quads
        const int count = 10 + int(u(rng) * 200.0f);
        Mesh batch[2];
        for (int q = 0; q < count; ++q) {
            const Vec3 c(8.0f * u(rng) - 4.0f, 0.3f + 3.5f * u(rng), 8.0f * u(rng) - 4.0f);
            const Vec3 a = glm::normalize(Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f));
            Vec3 t = glm::normalize(glm::cross(a, Vec3(0.3f, 1.0f, 0.2f)));
            const float size = 0.02f + 0.3f * u(rng);
            const Mesh quad = make_quad(c, t * size, glm::cross(a, t) * size, 0);
            Mesh& m = batch[q % 2];
            if (m.indices.empty())
                m = quad;
            else
                append_mesh(m, quad);
        }
        for (int k = 0; k < 2; ++k) {
            batch[k].material = lamps[3 * k];
            b.add_instance(b.add_mesh(batch[k]), Mat4(1));
        }
    }
    if (kind != 0) {  // an enclosure
        const float r = 6.0f + 4.0f * u(rng);
        b.add_instance(b.add_mesh(turned_inside_out(
                           make_sphere(r, 6 + int(u(rng) * 16), 8 + int(u(rng) * 24), lamps[1]))),
                       Mat4(1));
    }
    if (u(rng) < 0.5f)  // a second, brighter batch somewhere
        b.add_instance(b.add_mesh(make_sphere(0.2f + u(rng), 6, 8, lamps[2 + int(u(rng) * 2)])),
                       glm::translate(Mat4(1), Vec3(4 * u(rng) - 2, 1 + 2 * u(rng), -2)));
    return b.finish();
}

// The median over receivers of (tree's variance / power's), from every emitter's light and
// probability, with the same light model as the choice (centroid, distance kept above the
// triangle's size) written out here again.
double whole_sum_ratio(const ShadingScene& shading, const LightSampler& lights) {
    const SceneModel& scene = shading.model();
    const auto& emitters = lights.triangles();
    std::vector<double> ratios;
    for (const LightChoiceReceiver& r : light_choice_receivers(shading)) {
        double sum = 0.0, tree_second = 0.0, power_second = 0.0;
        for (std::size_t k = 0; k < emitters.size(); ++k) {
            const auto& e = emitters[k];
            const Material& m = scene.materials[std::size_t(e.material)];
            const Vec3 d = e.p0 + (e.e1 + e.e2) / 3.0f - r.p;
            const float d2 = glm::dot(d, d);
            const Vec3 w = d / std::sqrt(d2);
            const float out = m.double_sided ? std::abs(glm::dot(e.n, w)) : -glm::dot(e.n, w);
            const float in = glm::dot(r.n, w);
            if (!(out > 0.0f && in > 0.0f)) continue;
            const double f =
                double(luminance(m.emission())) * e.area * out * in / std::max(d2, e.area);
            const double by_tree = lights.tree().pmf(r.p, r.n, uint32_t(k));
            const double by_power = lights.cdf()[k] - (k ? lights.cdf()[k - 1] : 0.0f);
            sum += f;
            tree_second += f * f / by_tree;
            power_second += f * f / by_power;
        }
        if (!(sum > 0.0)) continue;
        const double v_tree = std::max(0.0, tree_second - sum * sum),
                     v_power = std::max(0.0, power_second - sum * sum);
        const double tiny = 1e-9 * sum * sum;
        ratios.push_back(v_tree <= tiny && v_power <= tiny ? 1.0
                                                           : v_tree / std::max(v_power, tiny));
    }
    if (ratios.empty()) return 1.0;
    std::nth_element(ratios.begin(), ratios.begin() + std::ptrdiff_t(ratios.size() / 2),
                     ratios.end());
    return ratios[ratios.size() / 2];
}

TEST(LightSamplerChoice, ItsReadingAgreesWithTheWholeSumOnRandomScenes) {
    std::mt19937 rng(2026);
    int decided = 0, first_looks = 0;
    for (int s = 0; s < 40; ++s) {
        const SceneModel scene = random_scene(rng);
        const ShadingScene shading(scene);
        const LightSampler tree(shading, {}, LightSelection::tree);
        const LightSampler chosen(shading, {}, LightSelection::automatic);
        const double exact = whole_sum_ratio(shading, tree);
        const double read = chosen.choice().variance_ratio;
        const bool first_look = chosen.choice().first_look;
        std::printf("scene %2d: %5zu emitters, whole sum %.3f, read %.3f, %s%s\n", s,
                    tree.triangle_count(), exact, read, light_selection_name(chosen.selection()),
                    first_look ? " (first look)" : "");
        first_looks += first_look;
        // A first look that decides reads a quarter of the receivers: its choice must be the
        // whole sum's, however far its median lies from the whole one (2.6x high on a scene
        // whose whole sum is 5x the threshold as GCC builds them; 7e8 against 40 on one as
        // clang does, where power's variance is nil at most of the first receivers).
        if (first_look) {
            EXPECT_EQ(chosen.selection(), exact < LightChoice::kTreeBelow ? LightSelection::tree
                                                                          : LightSelection::power)
                << "scene " << s << ": first look read " << read << ", whole sum " << exact;
            continue;
        }
        // 32 choices per receiver read the ratio within a factor of 2.2 on these scenes as GCC
        // builds them and 2.7 as clang does (its float arithmetic places the quads a little
        // otherwise); 16 choices within 3.3, with three decisions the whole sum would not make;
        // 64 still within 2.2. Far from the threshold such misreadings do not change the choice.
        EXPECT_LT(std::abs(std::log(read / exact)), std::log(3.0))
            << "scene " << s << ": read " << read << ", whole sum " << exact;
        // Away from the threshold the choice is the whole sum's.
        if (exact < 0.75 * LightChoice::kTreeBelow || exact > 1.33 * LightChoice::kTreeBelow) {
            ++decided;
            EXPECT_EQ(chosen.selection(), exact < LightChoice::kTreeBelow ? LightSelection::tree
                                                                          : LightSelection::power)
                << "scene " << s << ": whole sum " << exact;
        }
    }
    EXPECT_GT(decided, 10);
    EXPECT_GT(first_looks, 10);
}

}  // namespace
}  // namespace pathfarm
