// Materials: glTF 2.0 metallic-roughness with the KHR extensions pathfarm honours
// (emissive_strength, transmission, ior, specular, volume). Factors multiply textures.
#pragma once

#include <string>

#include "common/math/types.h"
#include "common/scene/texture.h"

namespace pathfarm {

// glTF alphaMode: OPAQUE ignores alpha; MASK keeps a hit where alpha >= alpha_cutoff; BLEND
// keeps a hit with probability alpha (stochastic transparency: common/scene/alpha.h).
enum class AlphaMode : uint8_t { opaque, mask, blend };
inline constexpr int kAlphaModeCount = 3;

struct Material {
    std::string name;

    Vec4 base_color_factor{1.0f};   // linear RGBA
    TextureRef base_color_texture;  // sRGB
    float metallic_factor = 1.0f;   // glTF defaults
    float roughness_factor = 1.0f;
    TextureRef metallic_roughness_texture;  // linear; G = roughness, B = metallic
    TextureRef normal_texture;              // tangent space, linear
    float normal_scale = 1.0f;

    // Emitted radiance = emissive_factor * emissive_strength * emissive texture (DESIGN.md).
    Rgb emissive_factor{0.0f};
    float emissive_strength = 1.0f;  // KHR_materials_emissive_strength
    TextureRef emissive_texture;     // sRGB

    float transmission_factor = 0.0f;  // KHR_materials_transmission
    float ior = 1.5f;                  // KHR_materials_ior
    float specular_factor = 1.0f;      // KHR_materials_specular: 0 gives a pure Lambert base
    Rgb specular_color_factor{1.0f};

    // KHR_materials_volume: Beer absorption inside transmissive objects. An infinite distance
    // means no absorption.
    Rgb attenuation_color{1.0f};
    float attenuation_distance = kInfinity;

    bool double_sided = false;  // emission from both faces; otherwise front (CCW) face only

    // Alpha = base_color_factor.a * base colour texture alpha.
    AlphaMode alpha_mode = AlphaMode::opaque;
    float alpha_cutoff = 0.5f;  // glTF default

    Rgb emission() const { return emissive_factor * emissive_strength; }
    bool is_emissive() const { return max_component(emission()) > 0.0f; }
    // Whether some hits on it may be discarded (its alpha can fall below "fully there").
    bool alpha_tested() const {
        if (alpha_mode == AlphaMode::opaque) return false;
        const float a = base_color_factor.a;
        return base_color_texture.valid() ||
               (alpha_mode == AlphaMode::mask ? !(a >= alpha_cutoff) : !(a >= 1.0f));
    }
};

}  // namespace pathfarm
