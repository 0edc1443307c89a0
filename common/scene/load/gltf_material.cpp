// glTF materials (metallic-roughness with the KHR extensions pathfarm honours), their
// textures and samplers.
#include "common/scene/load/gltf_material.h"

#include <spdlog/spdlog.h>
#include <tiny_gltf.h>

namespace pathfarm {
namespace {

float number(const tinygltf::Value& obj, const char* key, float fallback) {
    if (!obj.IsObject() || !obj.Has(key)) return fallback;
    const tinygltf::Value& v = obj.Get(key);
    return v.IsNumber() ? float(v.GetNumberAsDouble()) : fallback;
}

Rgb rgb_value(const tinygltf::Value& obj, const char* key, Rgb fallback) {
    if (!obj.IsObject() || !obj.Has(key)) return fallback;
    const tinygltf::Value& v = obj.Get(key);
    if (!v.IsArray() || v.ArrayLen() < 3) return fallback;
    return {float(v.Get(0).GetNumberAsDouble()), float(v.Get(1).GetNumberAsDouble()),
            float(v.Get(2).GetNumberAsDouble())};
}

const tinygltf::Value* extension(const tinygltf::ExtensionMap& map, const char* name) {
    const auto it = map.find(name);
    return it == map.end() ? nullptr : &it->second;
}

Vec2 vec2_value(const tinygltf::Value& obj, const char* key, Vec2 fallback) {
    if (!obj.IsObject() || !obj.Has(key)) return fallback;
    const tinygltf::Value& v = obj.Get(key);
    if (!v.IsArray() || v.ArrayLen() < 2) return fallback;
    return {float(v.Get(0).GetNumberAsDouble()), float(v.Get(1).GetNumberAsDouble())};
}

// A material's texture use (TextureInfo, NormalTextureInfo): index, set and KHR_texture_transform.
// Only TEXCOORD_0 is kept, so a use of another set warns and reads set 0.
template <typename Info>
TextureRef texture_ref(const Info& info, const std::string& path, const std::string& material) {
    TextureRef ref{info.index, 0, {}};
    if (ref.texture < 0) return ref;
    int set = info.texCoord;
    if (const auto* t = extension(info.extensions, "KHR_texture_transform")) {
        ref.transform.offset = vec2_value(*t, "offset", Vec2(0.0f));
        ref.transform.rotation = number(*t, "rotation", 0.0f);
        ref.transform.scale = vec2_value(*t, "scale", Vec2(1.0f));
        if (t->Has("texCoord")) set = int(number(*t, "texCoord", 0.0f));
    }
    if (set != 0)
        spdlog::warn("{}: material \"{}\": texture {} uses TEXCOORD_{}; only TEXCOORD_0 is read",
                     path, material, ref.texture, set);
    return ref;
}

AlphaMode alpha_mode(const std::string& mode) {
    if (mode == "MASK") return AlphaMode::mask;
    if (mode == "BLEND") return AlphaMode::blend;
    return AlphaMode::opaque;  // "OPAQUE", the default, and anything unknown
}

}  // namespace

void import_images_and_textures(const tinygltf::Model& gltf, const std::string& path,
                                SceneModel& scene) {
    for (const tinygltf::Image& img : gltf.images) {
        Image image;
        image.name = img.name.empty() ? img.uri : img.name;
        if (img.width > 0 && img.height > 0 &&
            img.image.size() == std::size_t(img.width) * img.height * 4) {
            image.width = img.width;
            image.height = img.height;
            image.rgba = img.image;
        } else if (img.image.empty() && img.width != 0) {
            spdlog::warn("{}: image \"{}\" could not be loaded; its texture is ignored", path,
                         img.uri);
        }
        scene.images.push_back(std::move(image));
    }
    for (const tinygltf::Texture& tex : gltf.textures) {
        Texture t;
        const bool valid = tex.source >= 0 && tex.source < int(scene.images.size()) &&
                           scene.images[tex.source].width > 0;
        t.image = valid ? tex.source : -1;
        if (tex.sampler >= 0 && tex.sampler < int(gltf.samplers.size())) {
            const tinygltf::Sampler& s = gltf.samplers[tex.sampler];
            t.sampler.filter = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST ? FilterMode::nearest
                                                                              : FilterMode::linear;
            const auto wrap = [](int w) {
                if (w == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return WrapMode::clamp_to_edge;
                if (w == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return WrapMode::mirrored_repeat;
                return WrapMode::repeat;
            };
            t.sampler.wrap_s = wrap(s.wrapS);
            t.sampler.wrap_t = wrap(s.wrapT);
        }
        scene.textures.push_back(t);
    }
}

void import_materials(const tinygltf::Model& gltf, const std::string& path, SceneModel& scene) {
    for (const tinygltf::Material& gm : gltf.materials) {
        Material m;
        m.name = gm.name;
        const auto& pbr = gm.pbrMetallicRoughness;
        for (int c = 0; c < 4 && c < int(pbr.baseColorFactor.size()); ++c)
            m.base_color_factor[c] = float(pbr.baseColorFactor[c]);
        m.base_color_texture = texture_ref(pbr.baseColorTexture, path, gm.name);
        m.metallic_factor = float(pbr.metallicFactor);
        m.roughness_factor = float(pbr.roughnessFactor);
        m.metallic_roughness_texture = texture_ref(pbr.metallicRoughnessTexture, path, gm.name);
        m.normal_texture = texture_ref(gm.normalTexture, path, gm.name);
        m.normal_scale = float(gm.normalTexture.scale);
        for (int c = 0; c < 3 && c < int(gm.emissiveFactor.size()); ++c)
            m.emissive_factor[c] = float(gm.emissiveFactor[c]);
        m.emissive_texture = texture_ref(gm.emissiveTexture, path, gm.name);
        m.double_sided = gm.doubleSided;
        m.alpha_mode = alpha_mode(gm.alphaMode);
        m.alpha_cutoff = float(gm.alphaCutoff);
        if (const auto* e = extension(gm.extensions, "KHR_materials_emissive_strength"))
            m.emissive_strength = number(*e, "emissiveStrength", 1.0f);
        if (const auto* e = extension(gm.extensions, "KHR_materials_transmission"))
            m.transmission_factor = number(*e, "transmissionFactor", 0.0f);
        if (const auto* e = extension(gm.extensions, "KHR_materials_ior"))
            m.ior = number(*e, "ior", 1.5f);
        if (const auto* e = extension(gm.extensions, "KHR_materials_specular")) {
            m.specular_factor = number(*e, "specularFactor", 1.0f);
            m.specular_color_factor = rgb_value(*e, "specularColorFactor", Rgb(1.0f));
        }
        if (const auto* e = extension(gm.extensions, "KHR_materials_volume")) {
            m.attenuation_distance = number(*e, "attenuationDistance", kInfinity);
            m.attenuation_color = rgb_value(*e, "attenuationColor", Rgb(1.0f));
        }
        scene.materials.push_back(std::move(m));
    }
}

}  // namespace pathfarm
