// First hits (common/film/first_hits.h) as the backends return them beside the radiance: each
// pixel's entry is what its centre ray meets first, or through mirrors and clear glass the
// surface beyond them, found here again by brute force in double precision over every
// triangle; asking for them leaves the radiance alone, any row split gives the same bytes, and
// the OpenCL backend agrees with Embree.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "common/math/transform.h"
#include "common/scene/load/builtin_scenes.h"
#include "tests/support/first_hit_reference.h"
#include "tests/support/render_helpers.h"

namespace pathfarm::first_hits_test {
namespace {

using test::Beyond;
using test::brute_force;
using test::follow_through;
using test::material_of;
using test::passes_light_on;
using test::ReferenceHit;
using tracer::BackendKind;

constexpr int kWidth = 40, kHeight = 24;

struct Rendered {
    std::vector<float> rgb;
    std::vector<FirstHit> hits;
};

FrameSpec spec_of(const SceneModel& scene, int first_sample) {
    return FrameSpec{kWidth, kHeight, 7, 11, 2, first_sample, scene.cameras.at(0)};
}

// Rows [0, kHeight) in the pieces `splits` separates; first hits only when `with_hits`.
Rendered render_rows(const SceneModel& scene, BackendKind kind, const FrameSpec& spec,
                     bool with_hits, const std::vector<int>& splits = {}) {
    auto backend = tracer::create_backend(kind, tracer::BackendOptions{2, 0, 0});
    EXPECT_TRUE(backend.ok()) << backend.error().message;
    EXPECT_TRUE((*backend)->set_scene(scene).ok());
    Rendered r{std::vector<float>(std::size_t(kWidth) * kHeight * 3),
               std::vector<FirstHit>(with_hits ? std::size_t(kWidth) * kHeight : 0)};
    std::vector<int> edges{0};
    edges.insert(edges.end(), splits.begin(), splits.end());
    edges.push_back(kHeight);
    for (std::size_t k = 0; k + 1 < edges.size(); ++k) {
        const std::size_t offset = std::size_t(edges[k]) * kWidth;
        tracer::RenderJob job{spec,     IntegratorSettings{},
                              edges[k], edges[k + 1],
                              {},       with_hits ? r.hits.data() + offset : nullptr};
        auto stats = (*backend)->render_rows(job, r.rgb.data() + 3 * offset);
        EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
    }
    return r;
}

SceneModel default_scene() {
    SceneModel scene = make_default_scene();
    recentre_on_camera(scene, scene.cameras.at(0));  // as tracers hold it
    return scene;
}

class FirstHits : public ::testing::TestWithParam<BackendKind> {};

TEST_P(FirstHits, AreWhatThePixelCentresRayMeetsFirst) {
    const SceneModel scene = default_scene();
    const FrameSpec spec = spec_of(scene, 3);
    const Rendered r = render_rows(scene, GetParam(), spec, true);
    int hits = 0, mismatched = 0, sharp = 0;
    int chains = 0, replaced = 0, replaced_right = 0, kept_sharp = 0, normal_wrong = 0, glossy = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const Ray ray = generate_camera_ray(spec.camera, kWidth, kHeight, x + 0.5f, y + 0.5f);
            const ReferenceHit want = brute_force(scene, ray);
            const FirstHit& got = r.hits[std::size_t(y) * kWidth + x];
            ASSERT_EQ(got.hit(), want.instance != FirstHit::kNone) << "pixel " << x << "," << y;
            if (!got.hit()) {
                EXPECT_TRUE(std::isinf(got.distance));
                continue;
            }
            ++hits;
            const Material& first = material_of(scene, want.instance);
            if (passes_light_on(first) && !first.metallic_roughness_texture.valid()) {
                const Beyond beyond = follow_through(scene, ray, want);
                chains += 1;
                if (beyond.replaced) {
                    ++replaced;
                    if (got.replaced() && got.instance == beyond.instance &&
                        std::abs(got.distance - beyond.travelled) < 1e-3 * beyond.travelled) {
                        ++replaced_right;
                        normal_wrong += glm::dot(glm::dvec3(got.normal), beyond.normal) < 0.999;
                    }
                } else if (got.sharp() && got.instance == want.instance) {
                    ++kept_sharp;
                }
                if (got.replaced()) {
                    EXPECT_EQ(got.primitive, FirstHit::kNone);
                    EXPECT_NEAR(glm::length(got.normal), 1.0f, 1e-3f);
                    EXPECT_LE(glm::dot(got.normal, ray.d), 1e-6f) << "the normal faces the camera";
                    continue;
                }
            }
            EXPECT_FALSE(got.replaced()) << "pixel " << x << "," << y;
            // A ray through a shared edge may take either triangle's instance.
            if (got.instance != want.instance) ++mismatched;
            EXPECT_NEAR(got.distance, want.t, 1e-4 * want.t + 1e-5) << "pixel " << x << "," << y;
            EXPECT_NEAR(glm::length(got.normal), 1.0f, 1e-3f);
            // The triangle and barycentrics name the hit point (deformed surfaces reproject by
            // them): its vertices so combined, placed by the instance, are where the ray hit.
            const Instance& inst = scene.instances[got.instance];
            const Mesh& mesh = scene.meshes[std::size_t(inst.mesh)];
            ASSERT_LT(std::size_t(got.primitive) * 3 + 2, mesh.indices.size());
            EXPECT_GE(got.u, 0.0f);
            EXPECT_GE(got.v, 0.0f);
            EXPECT_LE(got.u + got.v, 1.0f + 1e-5f);
            const uint32_t* tri = &mesh.indices[std::size_t(got.primitive) * 3];
            const Vec3 p =
                transform_point(inst.transform, (1.0f - got.u - got.v) * mesh.positions[tri[0]] +
                                                    got.u * mesh.positions[tri[1]] +
                                                    got.v * mesh.positions[tri[2]]);
            EXPECT_LT(glm::length(p - (ray.o + got.distance * ray.d)), 1e-4f * got.distance + 1e-5f)
                << "pixel " << x << "," << y;
            EXPECT_LE(glm::dot(got.normal, ray.d), 1e-6f) << "the normal faces the camera";
            const Material& m = scene.materials[std::size_t(
                scene.meshes[std::size_t(scene.instances[got.instance].mesh)].material)];
            if (!m.base_color_texture.valid()) {
                const Rgb base = glm::clamp(Rgb(m.base_color_factor), 0.0f, 1.0f);
                EXPECT_NEAR(glm::length(got.albedo - base), 0.0f, 1e-6f)
                    << "pixel " << x << "," << y;
            }
            // Sharp: an emitter seen from its emitting side, glass, or a mirror-like metal.
            const bool emits = max_component(m.emissive_factor) * m.emissive_strength > 0.0f &&
                               !m.emissive_texture.valid();
            const bool mirror = m.metallic_factor >= 0.5f &&
                                m.roughness_factor * m.roughness_factor < kSharpMaxAlpha &&
                                !m.metallic_roughness_texture.valid();
            if (!m.emissive_texture.valid() && !m.metallic_roughness_texture.valid()) {
                if (m.transmission_factor > 0.0f || mirror) {
                    EXPECT_TRUE(got.sharp()) << "pixel " << x << "," << y;
                } else if (!emits) {
                    EXPECT_FALSE(got.sharp()) << "pixel " << x << "," << y;
                    // Glossy: what is not sharp and smoother than kGlossyMaxAlpha (the marble
                    // pillars and the gold spheres).
                    const float alpha = m.roughness_factor * m.roughness_factor;
                    EXPECT_EQ(got.glossy(), alpha < kGlossyMaxAlpha) << "pixel " << x << "," << y;
                    glossy += got.glossy();
                }
            }
            sharp += got.sharp();
        }
    EXPECT_GT(hits, kWidth * kHeight / 2);
    EXPECT_LE(mismatched, hits / 100);
    EXPECT_GT(sharp, 0) << "builtin:default shows an emitter, glass and a mirror";
    EXPECT_GT(glossy, 10) << "builtin:default shows marble pillars and gold spheres";
    // Through the mirror and the glass sphere: the surface beyond, where double precision
    // finds it (a chain's float rounding may end on another triangle at grazing angles).
    EXPECT_GT(replaced, 10) << "builtin:default's view shows its mirror and glass sphere";
    EXPECT_GE(replaced_right, replaced * 9 / 10) << replaced_right << " of " << replaced;
    // Their normals as the mirror shows them (a flat floor seen in a flat mirror stays flat).
    EXPECT_LE(normal_wrong, replaced_right / 50) << normal_wrong << " of " << replaced_right;
    EXPECT_GE(kept_sharp + replaced, chains * 9 / 10);
}

TEST_P(FirstHits, LeaveTheRadianceAloneAndAgreeForAnySplit) {
    const SceneModel scene = default_scene();
    const FrameSpec spec = spec_of(scene, 0);
    const Rendered plain = render_rows(scene, GetParam(), spec, false);
    const Rendered whole = render_rows(scene, GetParam(), spec, true);
    const Rendered split = render_rows(scene, GetParam(), spec, true, {4, 5, 17});
    ASSERT_EQ(std::memcmp(plain.rgb.data(), whole.rgb.data(), plain.rgb.size() * sizeof(float)), 0);
    ASSERT_EQ(std::memcmp(whole.rgb.data(), split.rgb.data(), whole.rgb.size() * sizeof(float)), 0);
    ASSERT_EQ(
        std::memcmp(whole.hits.data(), split.hits.data(), whole.hits.size() * sizeof(FirstHit)), 0);
}

INSTANTIATE_TEST_SUITE_P(Backends, FirstHits, ::testing::ValuesIn(test::built_backends()),
                         test::BackendTestName{});

#ifdef PATHFARM_HAS_OPENCL
// The kernel's first hits against Embree's: the same surfaces, within float differences.
TEST(FirstHitsAcrossBackends, OpenClAgreesWithEmbree) {
    const SceneModel scene = default_scene();
    const FrameSpec spec = spec_of(scene, 1);
    const Rendered e = render_rows(scene, BackendKind::embree, spec, true);
    const Rendered c = render_rows(scene, BackendKind::opencl, spec, true);
    int same = 0, other_triangle = 0;
    for (std::size_t i = 0; i < e.hits.size(); ++i) {
        const FirstHit &a = e.hits[i], &b = c.hits[i];
        if (a.instance != b.instance) continue;
        ++same;
        if (!a.hit()) continue;
        EXPECT_NEAR(a.distance, b.distance, 1e-4f * a.distance) << "pixel " << i;
        EXPECT_GT(glm::dot(a.normal, b.normal), 0.999f) << "pixel " << i;
        EXPECT_LT(glm::length(a.albedo - b.albedo), 2e-3f) << "pixel " << i;
        EXPECT_EQ(a.flags, b.flags) << "pixel " << i;
        if (a.primitive != b.primitive) {  // a ray through a shared edge
            ++other_triangle;
            continue;
        }
        EXPECT_NEAR(a.u, b.u, 1e-3f) << "pixel " << i;
        EXPECT_NEAR(a.v, b.v, 1e-3f) << "pixel " << i;
    }
    EXPECT_GE(same, int(e.hits.size()) * 99 / 100);
    EXPECT_LE(other_triangle, same / 100);
}
#endif

}  // namespace
}  // namespace pathfarm::first_hits_test
