// Surface reconstruction from (instance, primitive, barycentrics) and material evaluation.
#include "common/render/shading_scene.h"

#include "common/math/frame.h"
#include "common/math/transform.h"

namespace pathfarm {
namespace {

Vec3 normalize_or(const Vec3& v, const Vec3& fallback) {
    const float len2 = glm::dot(v, v);
    return len2 > 1e-20f && std::isfinite(len2) ? v / std::sqrt(len2) : fallback;
}

}  // namespace

ShadingScene::ShadingScene(const SceneModel& scene, const TextureMips* mips)
    : scene_(scene), mips_(mips) {
    normal_matrices_.reserve(scene.instances.size());
    handedness_.reserve(scene.instances.size());
    for (const Instance& inst : scene.instances) {
        normal_matrices_.push_back(normal_matrix(inst.transform));
        handedness_.push_back(glm::determinant(Mat3(inst.transform)) < 0.0f ? -1.0f : 1.0f);
    }
}

void ShadingScene::triangle_vertices(uint32_t instance, uint32_t prim, Vec3 p[3]) const {
    const Instance& inst = scene_.instances[instance];
    const Mesh& mesh = scene_.meshes[inst.mesh];
    for (int k = 0; k < 3; ++k)
        p[k] = transform_point(inst.transform, mesh.positions[mesh.indices[3 * prim + k]]);
}

SurfacePoint ShadingScene::surface(const Hit& hit) const {
    const Instance& inst = scene_.instances[hit.instance];
    const Mesh& mesh = scene_.meshes[inst.mesh];
    const uint32_t i[3] = {mesh.indices[3 * hit.prim], mesh.indices[3 * hit.prim + 1],
                           mesh.indices[3 * hit.prim + 2]};
    Vec3 p[3];
    triangle_vertices(hit.instance, hit.prim, p);
    const float b0 = 1.0f - hit.u - hit.v;
    SurfacePoint sp;
    sp.material = mesh.material;
    // Barycentric interpolation of world vertices is far more precise than o + t d.
    sp.p = b0 * p[0] + hit.u * p[1] + hit.v * p[2];
    // glTF: a negative-determinant transform flips the winding, so the front face keeps
    // following the transformed normal.
    const Vec3 cross = glm::cross(p[1] - p[0], p[2] - p[0]);
    sp.ng = normalize_or(cross * handedness_[hit.instance], Vec3(0, 0, 1));
    sp.ns = sp.ng;
    const Mat3& nm = normal_matrices_[hit.instance];
    if (mesh.has_normals()) {
        const Vec3 n =
            b0 * mesh.normals[i[0]] + hit.u * mesh.normals[i[1]] + hit.v * mesh.normals[i[2]];
        sp.ns = normalize_or(nm * n, sp.ng);
        if (glm::dot(sp.ns, sp.ng) < 0.0f) sp.ns = -sp.ns;
    }
    if (mesh.has_uvs()) {
        const Vec2 t[3] = {mesh.uvs[i[0]], mesh.uvs[i[1]], mesh.uvs[i[2]]};
        sp.uv = b0 * t[0] + hit.u * t[1] + hit.v * t[2];
        if (mips_) {  // both areas doubled: the ratio is the triangle's
            const Vec2 e1 = t[1] - t[0], e2 = t[2] - t[0];
            const float world = glm::length(cross);
            const float density = std::abs(e1.x * e2.y - e1.y * e2.x) / world;
            sp.uv_density = std::isfinite(density) ? density : 0.0f;
        }
    }
    if (mesh.has_tangents()) {
        const Vec4 t =
            b0 * mesh.tangents[i[0]] + hit.u * mesh.tangents[i[1]] + hit.v * mesh.tangents[i[2]];
        sp.tangent = Mat3(inst.transform) * Vec3(t);
        sp.bitangent_sign = (t.w < 0.0f ? -1.0f : 1.0f) * handedness_[hit.instance];
    }
    return sp;
}

const Image* ShadingScene::texture_level(const TextureRef& ref, const SurfacePoint& sp,
                                         float footprint) const {
    const Image* image = scene_.texture_image(ref);
    if (footprint <= 0.0f || !mips_ || !image) return image;
    const std::vector<Image>& levels = mips_->levels(scene_.textures[ref.texture].image);
    const Vec2 scale = ref.transform.scale;
    const float texels = footprint * sp.uv_density * std::abs(scale.x * scale.y) *
                         float(image->width) * float(image->height);
    const int level = mip_level(texels, int(levels.size()));
    return level == 0 ? image : &levels[std::size_t(level - 1)];
}

MaterialPoint ShadingScene::material_point(SurfacePoint& sp, float footprint) const {
    const Material& m = scene_.materials[sp.material];
    MaterialPoint mp;
    Vec4 base = m.base_color_factor;
    if (m.base_color_texture.valid())
        base *= sample_image(texture_level(m.base_color_texture, sp, footprint),
                             scene_.textures[m.base_color_texture.texture].sampler,
                             m.base_color_texture.uv(sp.uv), true);
    mp.base_color = glm::clamp(Rgb(base), Rgb(0.0f), Rgb(1.0f));
    float roughness = m.roughness_factor;
    float metallic = m.metallic_factor;
    if (m.metallic_roughness_texture.valid()) {
        const Vec4 mr = sample_image(texture_level(m.metallic_roughness_texture, sp, footprint),
                                     scene_.textures[m.metallic_roughness_texture.texture].sampler,
                                     m.metallic_roughness_texture.uv(sp.uv), false);
        roughness *= mr.y;
        metallic *= mr.z;
    }
    roughness = std::clamp(std::isfinite(roughness) ? roughness : 1.0f, 0.0f, 1.0f);
    mp.alpha = roughness * roughness;
    mp.metallic = std::clamp(std::isfinite(metallic) ? metallic : 0.0f, 0.0f, 1.0f);
    mp.transmission = m.transmission_factor;
    mp.ior = m.ior;
    mp.specular = m.specular_factor;
    mp.specular_color = m.specular_color_factor;
    if (m.normal_texture.valid() && glm::dot(sp.tangent, sp.tangent) > 0.0f) {
        const Vec4 t = sample_image(texture_level(m.normal_texture, sp, footprint),
                                    scene_.textures[m.normal_texture.texture].sampler,
                                    m.normal_texture.uv(sp.uv), false);
        Vec3 tn = Vec3(t) * 2.0f - Vec3(1.0f);
        tn.x *= m.normal_scale;
        tn.y *= m.normal_scale;
        const Frame f = Frame::from_normal_tangent(sp.ns, sp.tangent);
        const Vec3 n =
            normalize_or(f.t * tn.x + f.b * (tn.y * sp.bitangent_sign) + sp.ns * tn.z, sp.ns);
        if (glm::dot(n, sp.ng) > 0.0f) sp.ns = n;
    }
    return mp;
}

Rgb ShadingScene::emitted(const SurfacePoint& sp, const Vec3& wo) const {
    const Material& m = scene_.materials[sp.material];
    if (!m.is_emissive()) return Rgb(0.0f);
    if (!m.double_sided && glm::dot(wo, sp.ng) <= 0.0f) return Rgb(0.0f);
    Rgb le = m.emission();
    if (m.emissive_texture.valid())
        le *= Rgb(sample_image(scene_.texture_image(m.emissive_texture),
                               scene_.textures[m.emissive_texture.texture].sampler,
                               m.emissive_texture.uv(sp.uv), true));
    return le;
}

Rgb ShadingScene::absorption_coefficient(int material) const {
    const Material& m = scene_.materials[material];
    if (!std::isfinite(m.attenuation_distance) || m.attenuation_distance <= 0.0f) return Rgb(0.0f);
    const Rgb c = glm::clamp(m.attenuation_color, Rgb(1e-6f), Rgb(1.0f));
    return -glm::log(c) / m.attenuation_distance;
}

}  // namespace pathfarm
