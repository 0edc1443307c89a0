// content_hash(SceneState): FNV-1a over a canonical byte stream of the state.
#include <cstring>
#include <string>

#include "common/base/hash.h"
#include "common/scene/scene_state.h"

namespace pathfarm {
namespace {

class Hasher {
public:
    void bytes(const void* data, std::size_t size) {
        h_ = fnv1a64(static_cast<const unsigned char*>(data), size, h_);
    }
    template <typename T>
    void pod(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes(&v, sizeof(T));
    }
    template <typename T>
    void array(const std::vector<T>& v) {
        pod(uint64_t(v.size()));
        if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
    }
    void string(const std::string& s) {
        pod(uint64_t(s.size()));
        bytes(s.data(), s.size());
    }
    uint64_t value() const { return h_; }

private:
    uint64_t h_ = 0xcbf29ce484222325ULL;
};

void hash_material(Hasher& h, const Material& m) {
    h.string(m.name);
    h.pod(m.base_color_factor);
    for (const TextureRef* t : {&m.base_color_texture, &m.metallic_roughness_texture,
                                &m.normal_texture, &m.emissive_texture}) {
        h.pod(t->texture);
        h.pod(t->texcoord);
        h.pod(t->transform.offset);
        h.pod(t->transform.rotation);
        h.pod(t->transform.scale);
    }
    h.pod(m.metallic_factor);
    h.pod(m.roughness_factor);
    h.pod(m.normal_scale);
    h.pod(m.emissive_factor);
    h.pod(m.emissive_strength);
    h.pod(m.transmission_factor);
    h.pod(m.ior);
    h.pod(m.specular_factor);
    h.pod(m.specular_color_factor);
    h.pod(m.attenuation_color);
    h.pod(m.attenuation_distance);
    h.pod(m.double_sided);
    h.pod(m.alpha_mode);
    h.pod(m.alpha_cutoff);
}

void hash_mesh(Hasher& h, const Mesh& m) {
    h.string(m.name);
    h.array(m.positions);
    h.array(m.normals);
    h.array(m.uvs);
    h.array(m.tangents);
    h.array(m.indices);
    h.pod(m.material);
}

}  // namespace

uint64_t content_hash(const SceneState& s) {
    Hasher h;
    for (const auto& [id, image] : s.images) {
        h.pod(id);
        h.string(image.name);
        h.pod(image.width);
        h.pod(image.height);
        h.array(image.rgba);
    }
    for (const auto& [id, t] : s.textures) {
        h.pod(id);
        h.pod(t.image);
        h.pod(uint8_t(t.sampler.filter));
        h.pod(uint8_t(t.sampler.wrap_s));
        h.pod(uint8_t(t.sampler.wrap_t));
    }
    for (const auto& [id, m] : s.materials) {
        h.pod(id);
        hash_material(h, m);
    }
    for (const auto& [id, m] : s.meshes) {
        h.pod(id);
        hash_mesh(h, m);
    }
    for (const auto& [id, inst] : s.instances) {
        h.pod(id);
        h.pod(inst.mesh);
        h.pod(inst.transform);
        h.pod(inst.dynamic);
    }
    for (const auto& [id, c] : s.cameras) {
        h.pod(id);
        h.string(c.name);
        h.pod(c.camera_to_world);
        h.pod(c.yfov_radians);
    }
    h.pod(s.active_camera);
    // Field by field: whole structs would hash their padding bytes.
    h.pod(uint8_t(s.environment.sky));
    h.pod(s.environment.sun_direction);
    h.pod(s.environment.turbidity);
    h.pod(s.environment.sun_scale);
    h.pod(s.settings.width);
    h.pod(s.settings.height);
    h.pod(s.settings.spp);
    h.pod(s.settings.max_depth);
    h.pod(s.settings.seed);
    return h.value();
}

}  // namespace pathfarm
