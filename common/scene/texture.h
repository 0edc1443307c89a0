// Images and textures with glTF sampler semantics. Texel data is 8-bit RGBA, row 0 at the top;
// whether it holds sRGB-encoded colour or linear data is decided by the use (TextureRef).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/math/types.h"

namespace pathfarm {

struct Image {
    std::string name;
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;  // width * height * 4 bytes
};

enum class WrapMode : uint8_t { repeat, clamp_to_edge, mirrored_repeat };
inline constexpr int kWrapModeCount = 3;
enum class FilterMode : uint8_t { nearest, linear };
inline constexpr int kFilterModeCount = 2;

struct Sampler {
    // glTF magFilter. The glTF minFilter is not read: the camera's hits read level 0 (the
    // pixel's samples average the footprint), later vertices a mip level chosen by the path's
    // ray cone (texture_mips.h).
    FilterMode filter = FilterMode::linear;
    WrapMode wrap_s = WrapMode::repeat;
    WrapMode wrap_t = WrapMode::repeat;
};

struct Texture {
    int image = -1;  // index into SceneModel::images; -1 if the image could not be decoded
    Sampler sampler;
};

// KHR_texture_transform: uv' = offset + R(rotation) (scale * uv), with R the spec's
// [cos sin; -sin cos] (a positive rotation turns the image clockwise in uv, glTF's v pointing
// down). The identity by default.
struct UvTransform {
    Vec2 offset{0.0f};
    float rotation = 0.0f;  // radians
    Vec2 scale{1.0f};

    bool identity() const {
        return offset == Vec2(0.0f) && rotation == 0.0f && scale == Vec2(1.0f);
    }
    Vec2 apply(Vec2 uv) const {
        if (identity()) return uv;
        const float c = std::cos(rotation), s = std::sin(rotation);
        const Vec2 q = scale * uv;
        return offset + Vec2(c * q.x + s * q.y, -s * q.x + c * q.y);
    }
};

// A material's use of a texture. texture < 0 means "no texture".
struct TextureRef {
    int texture = -1;
    int texcoord = 0;  // only TEXCOORD_0 is kept by the loaders
    UvTransform transform;
    bool valid() const { return texture >= 0; }
    Vec2 uv(Vec2 mesh_uv) const { return transform.apply(mesh_uv); }
};

// Filtered lookup at uv (glTF: (0,0) is the top-left corner of the image). Returns RGBA in
// [0,1]; with srgb the RGB channels are decoded from sRGB to linear. A missing image gives
// opaque white so that a texture that failed to decode leaves the factor alone.
Vec4 sample_image(const Image* image, const Sampler& sampler, Vec2 uv, bool srgb);

float srgb_to_linear(float v);
// srgb_to_linear of every 8-bit code.
const std::array<float, 256>& srgb_decode_table();
float linear_to_srgb(float v);

}  // namespace pathfarm
