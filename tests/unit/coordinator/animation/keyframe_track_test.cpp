// Keyframe interpolation against hand-computed values and the InterpolationTest sample model.
#include "coordinator/animation/keyframe_track.h"

#include <gtest/gtest.h>
#include <glm/gtc/quaternion.hpp>

#include "common/scene/load/scene_loader.h"
#include "coordinator/animation/animator.h"
#include "tests/support/test_env.h"

namespace pathfarm::coord {
namespace {

AnimationSampler curve(Interpolation interp, std::vector<float> times, std::vector<float> values,
                       int comps) {
    AnimationSampler s;
    s.interpolation = interp;
    s.times = std::move(times);
    s.values = std::move(values);
    s.components = comps;
    return s;
}

float at(const AnimationSampler& s, float t) {
    float v = 0.0f;
    sample_keyframes(s, t, 1, false, &v);
    return v;
}

TEST(Keyframes, StepLinearAndClamping) {
    const auto step = curve(Interpolation::step, {1, 2, 4}, {10, 20, 40}, 1);
    const auto lin = curve(Interpolation::linear, {1, 2, 4}, {10, 20, 40}, 1);
    EXPECT_EQ(at(step, 0.0f), 10.0f);  // before the first key
    EXPECT_EQ(at(step, 1.9f), 10.0f);
    EXPECT_EQ(at(step, 2.0f), 20.0f);
    EXPECT_EQ(at(step, 9.0f), 40.0f);  // after the last key
    EXPECT_FLOAT_EQ(at(lin, 1.5f), 15.0f);
    EXPECT_FLOAT_EQ(at(lin, 3.0f), 30.0f);
    EXPECT_EQ(at(lin, 5.0f), 40.0f);
}

TEST(Keyframes, CubicSplineScalesTangentsByTheInterval) {
    // keys at t=0 and t=2: value 0 then 1; out-tangent of key 0 = 3, in-tangent of key 1 = -1.
    // Layout per key: in-tangent, value, out-tangent.
    const auto s = curve(Interpolation::cubic_spline, {0, 2}, {9, 0, 3, -1, 1, 9}, 1);
    const double u = 0.25, dt = 2.0;
    const double expected = (2 * u * u * u - 3 * u * u + 1) * 0 +
                            (u * u * u - 2 * u * u + u) * dt * 3 +
                            (-2 * u * u * u + 3 * u * u) * 1 + (u * u * u - u * u) * dt * -1;
    EXPECT_NEAR(at(s, 0.5f), expected, 1e-6);
    EXPECT_EQ(at(s, 0.0f), 0.0f);
    EXPECT_EQ(at(s, 2.0f), 1.0f);
}

TEST(Keyframes, SlerpTakesTheShortestPath) {
    const glm::quat a = glm::angleAxis(0.0f, Vec3(0, 1, 0));
    const glm::quat b =
        -glm::angleAxis(glm::radians(90.0f), Vec3(0, 1, 0));  // same rotation, far hemisphere
    const float qa[4] = {a.x, a.y, a.z, a.w}, qb[4] = {b.x, b.y, b.z, b.w};
    float out[4];
    slerp(qa, qb, 0.5, out);
    const glm::quat r(out[3], out[0], out[1], out[2]);
    const glm::quat expected = glm::angleAxis(glm::radians(45.0f), Vec3(0, 1, 0));
    EXPECT_NEAR(std::abs(glm::dot(r, expected)), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::length(r), 1.0f, 1e-6f);
}

// Independent evaluation for the sample model: glTF Appendix C written out with glm.
Vec4 reference_value(const AnimationSampler& s, float t, int comps) {
    const auto value = [&](std::size_t k, int part) {
        const std::size_t stride = s.interpolation == Interpolation::cubic_spline ? 3 : 1;
        Vec4 v(0.0f);
        for (int c = 0; c < comps; ++c)
            v[c] = s.values[(k * stride + part) * comps + c];
        return v;
    };
    const int mid = s.interpolation == Interpolation::cubic_spline ? 1 : 0;
    if (t <= s.times.front()) return value(0, mid);
    if (t >= s.times.back()) return value(s.times.size() - 1, mid);
    std::size_t k = 0;
    while (s.times[k + 1] <= t)
        ++k;
    const float dt = s.times[k + 1] - s.times[k], u = (t - s.times[k]) / dt;
    if (s.interpolation == Interpolation::step) return value(k, 0);
    if (s.interpolation == Interpolation::linear) {
        if (comps == 4) {
            glm::quat a(value(k, 0).w, value(k, 0).x, value(k, 0).y, value(k, 0).z);
            glm::quat b(value(k + 1, 0).w, value(k + 1, 0).x, value(k + 1, 0).y, value(k + 1, 0).z);
            if (glm::dot(a, b) < 0.0f) b = -b;
            const glm::quat q = glm::normalize(glm::slerp(a, b, u));
            return {q.x, q.y, q.z, q.w};
        }
        return glm::mix(value(k, 0), value(k + 1, 0), u);
    }
    const Vec4 p = (2 * u * u * u - 3 * u * u + 1) * value(k, 1) +
                   (u * u * u - 2 * u * u + u) * dt * value(k, 2) +
                   (-2 * u * u * u + 3 * u * u) * value(k + 1, 1) +
                   (u * u * u - u * u) * dt * value(k + 1, 0);
    return comps == 4 ? glm::normalize(p) : p;
}

Vec4 node_value(const Node& n, AnimationPath path) {
    if (path == AnimationPath::translation) return Vec4(n.translation, 0.0f);
    if (path == AnimationPath::scale) return Vec4(n.scale, 0.0f);
    return {n.rotation.x, n.rotation.y, n.rotation.z, n.rotation.w};
}

TEST(Animator, InterpolationTestMatchesKeysAndAnalyticValues) {
    PF_REQUIRE_SCENES(scenes);
    auto scene = load_scene(scenes + "/interpolation-test/InterpolationTest.gltf");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    ASSERT_EQ(scene->animations.size(), 9u);
    int checked = 0;
    for (std::size_t c = 0; c < scene->animations.size(); ++c) {
        const AnimationClip& clip = scene->animations[c];
        const AnimationChannel& ch = clip.channels.at(0);
        const AnimationSampler& s = clip.samplers[ch.sampler];
        const int comps = ch.path == AnimationPath::rotation ? 4 : 3;
        std::vector<float> times = s.times;
        for (std::size_t k = 0; k + 1 < s.times.size(); ++k)
            for (float f : {0.25f, 0.5f, 0.8f})
                times.push_back(s.times[k] + f * (s.times[k + 1] - s.times[k]));
        for (float t : times) {
            SceneModel copy = *scene;
            apply_clip(copy, int(c), t);
            const Vec4 got = node_value(copy.nodes[ch.node], ch.path);
            Vec4 want = reference_value(s, t, comps);
            if (comps == 4 && glm::dot(got, want) < 0.0f)
                want = -want;  // q and -q are one rotation
            for (int i = 0; i < comps; ++i)
                EXPECT_NEAR(got[i], want[i], 1e-5f) << clip.name << " t=" << t;
            ++checked;
        }
    }
    EXPECT_GT(checked, 50);
}

TEST(Animator, FindsClipsByNameOrIndex) {
    SceneModel scene;
    scene.animations.resize(2);
    scene.animations[1].name = "Walk";
    EXPECT_EQ(*find_clip(scene, "Walk"), 1);
    EXPECT_EQ(*find_clip(scene, "0"), 0);
    EXPECT_FALSE(find_clip(scene, "Run").ok());
    EXPECT_FALSE(find_clip(scene, "2").ok());
}

}  // namespace
}  // namespace pathfarm::coord
