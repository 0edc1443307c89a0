// Brute-force first hits (first_hit_reference.h).
#include "tests/support/first_hit_reference.h"

#include <cmath>
#include <vector>

#include "common/math/transform.h"
#include "common/render/path_tracer.h"

namespace pathfarm::test {
namespace {

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

}  // namespace

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

}  // namespace pathfarm::test
