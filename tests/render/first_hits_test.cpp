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
#include "tests/support/render_helpers.h"

namespace pathfarm::first_hits_test {
namespace {

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

struct ReferenceHit {
    double t = INFINITY;
    uint32_t instance = FirstHit::kNone;
    uint32_t prim = 0;
    double u = 0.0, v = 0.0;
};

// Closest hit of `ray` over every triangle of every instance (Moller-Trumbore, double).
ReferenceHit brute_force(const SceneModel& scene, const Ray& ray) {
    const glm::dvec3 o(ray.o), d(ray.d);
    ReferenceHit best;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        const Mesh& mesh = scene.meshes[std::size_t(inst.mesh)];
        for (std::size_t p = 0; p < mesh.indices.size() / 3; ++p) {
            glm::dvec3 v[3];
            for (int k = 0; k < 3; ++k)
                v[k] = glm::dvec3(
                    transform_point(inst.transform, mesh.positions[mesh.indices[3 * p + k]]));
            const glm::dvec3 e1 = v[1] - v[0], e2 = v[2] - v[0], q = glm::cross(d, e2);
            const double det = glm::dot(e1, q);
            if (std::abs(det) < 1e-300) continue;
            const glm::dvec3 s = o - v[0], r = glm::cross(s, e1);
            const double u = glm::dot(s, q) / det, w = glm::dot(d, r) / det;
            const double t = glm::dot(e2, r) / det;
            if (u >= 0.0 && w >= 0.0 && u + w <= 1.0 && t > 1e-4 && t < best.t)
                best = {t, uint32_t(i), uint32_t(p), u, w};
        }
    }
    return best;
}

const Material& material_of(const SceneModel& scene, uint32_t instance) {
    return scene
        .materials[std::size_t(scene.meshes[std::size_t(scene.instances[instance].mesh)].material)];
}

// What the denoiser is shown through a mirror-like metal or clear glass: the first other
// surface, the length of the path to it, and whether the path got there (an emitter or the sky
// on the way, or more than kMaxReplacedBounces of them, leave the first hit as it was).
struct Beyond {
    bool replaced = false;
    double travelled = 0.0;
    uint32_t instance = FirstHit::kNone;
    glm::dvec3 normal{0.0};  // as the mirrors passed show it, facing the camera
};

// The shading normal at `hit`, in double: the mesh's normals interpolated and placed.
glm::dvec3 shading_normal(const SceneModel& scene, const ReferenceHit& hit) {
    const Instance& inst = scene.instances[hit.instance];
    const Mesh& mesh = scene.meshes[std::size_t(inst.mesh)];
    const uint32_t* tri = &mesh.indices[std::size_t(hit.prim) * 3];
    const glm::dvec3 n = (1.0 - hit.u - hit.v) * glm::dvec3(mesh.normals[tri[0]]) +
                         hit.u * glm::dvec3(mesh.normals[tri[1]]) +
                         hit.v * glm::dvec3(mesh.normals[tri[2]]);
    return glm::normalize(glm::dmat3(normal_matrix(inst.transform)) * n);
}

bool passes_light_on(const Material& m) {
    const bool smooth = m.roughness_factor * m.roughness_factor < kSharpMaxAlpha;
    return !m.is_emissive() && smooth &&
           (m.transmission_factor > 0.0f || m.metallic_factor >= 0.5f);
}

Beyond follow_through(const SceneModel& scene, Ray ray, ReferenceHit hit) {
    Beyond b;
    const glm::dvec3 camera_d(ray.d);
    std::vector<glm::dvec3> mirrors;
    for (int bounce = 0; hit.instance != FirstHit::kNone; ++bounce) {
        const Material& m = material_of(scene, hit.instance);
        const glm::dvec3 d(ray.d), p = glm::dvec3(ray.o) + hit.t * d;
        const glm::dvec3 n = shading_normal(scene, hit);
        b.travelled += hit.t;
        if (!passes_light_on(m)) {
            b.replaced = bounce > 0 && !m.is_emissive() && m.transmission_factor == 0.0f;
            b.instance = hit.instance;
            b.normal = n;
            for (auto k = mirrors.rbegin(); k != mirrors.rend(); ++k)
                b.normal -= 2.0 * glm::dot(b.normal, *k) * *k;
            if (glm::dot(b.normal, camera_d) > 0.0) b.normal = -b.normal;
            return b;
        }
        if (bounce == kMaxReplacedBounces) return b;
        glm::dvec3 next = d - 2.0 * glm::dot(d, n) * n;  // a mirror, or total internal reflection
        bool refracted = false;
        if (m.transmission_factor > 0.0f) {
            double cos_i = -glm::dot(d, n), eta = m.ior;
            glm::dvec3 towards = n;
            if (cos_i < 0.0) cos_i = -cos_i, eta = 1.0 / eta, towards = -n;
            const double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
            if (sin2_t < 1.0) {
                next = d / eta + (cos_i / eta - std::sqrt(1.0 - sin2_t)) * towards;
                refracted = true;
            }
        }
        if (!refracted) mirrors.push_back(n);
        ray.o = Vec3(p);
        ray.d = Vec3(glm::normalize(next));
        hit = brute_force(scene, ray);
    }
    return b;
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
