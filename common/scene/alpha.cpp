// Alpha coverage and stochastic transparency.
#include "common/scene/alpha.h"

#include <bit>

#include "common/base/hash.h"

namespace pathfarm {

float base_color_alpha(const SceneModel& scene, const Material& m, Vec2 uv) {
    float a = m.base_color_factor.a;
    if (m.base_color_texture.valid())
        a *= sample_image(scene.texture_image(m.base_color_texture),
                          scene.textures[std::size_t(m.base_color_texture.texture)].sampler,
                          m.base_color_texture.uv(uv), true)
                 .a;
    return a;
}

float alpha_coverage(const Material& m, float alpha) {
    switch (m.alpha_mode) {
        case AlphaMode::mask:
            return alpha >= m.alpha_cutoff ? 1.0f : 0.0f;
        case AlphaMode::blend:
            return std::clamp(alpha, 0.0f, 1.0f);
        case AlphaMode::opaque:
        default:
            return 1.0f;
    }
}

float alpha_hash(const Vec3& o, const Vec3& d, float t, uint32_t prim) {
    const auto b = [](float f) { return std::bit_cast<uint32_t>(f); };
    const uint32_t h = hash_words({b(o.x), b(o.y), b(o.z), b(d.x), b(d.y), b(d.z), b(t), prim});
    return float(h >> 8) * 0x1p-24f;
}

bool alpha_keeps_hit(const SceneModel& scene, const Mesh& mesh, uint32_t prim, float u, float v,
                     const Vec3& o, const Vec3& d, float t) {
    const Material& m = scene.materials[std::size_t(mesh.material)];
    Vec2 uv(0.0f);
    if (mesh.has_uvs()) {
        const uint32_t* i = &mesh.indices[3 * std::size_t(prim)];
        uv = (1.0f - u - v) * mesh.uvs[i[0]] + u * mesh.uvs[i[1]] + v * mesh.uvs[i[2]];
    }
    const float alpha = base_color_alpha(scene, m, uv);
    return alpha_keeps_hit(m, alpha,
                           m.alpha_mode == AlphaMode::blend ? alpha_hash(o, d, t, prim) : 0.0f);
}

}  // namespace pathfarm
