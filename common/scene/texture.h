// Images and textures with glTF sampler semantics. Texel data is 8-bit RGBA, row 0 at the top;
// whether it holds sRGB-encoded colour or linear data is decided by the use (TextureRef).
#pragma once

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
enum class FilterMode : uint8_t { nearest, linear };

struct Sampler {
    FilterMode filter = FilterMode::linear;  // glTF magFilter; we do not mip-map (path tracing
                                             // averages many samples per pixel)
    WrapMode wrap_s = WrapMode::repeat;
    WrapMode wrap_t = WrapMode::repeat;
};

struct Texture {
    int image = -1;  // index into SceneModel::images; -1 if the image could not be decoded
    Sampler sampler;
};

// A material's use of a texture. texture < 0 means "no texture".
struct TextureRef {
    int texture = -1;
    int texcoord = 0;  // only TEXCOORD_0 is kept by the loaders
    bool valid() const { return texture >= 0; }
};

// Filtered lookup at uv (glTF: (0,0) is the top-left corner of the image). Returns RGBA in
// [0,1]; with srgb the RGB channels are decoded from sRGB to linear. A missing image gives
// opaque white so that a texture that failed to decode leaves the factor alone.
Vec4 sample_image(const Image* image, const Sampler& sampler, Vec2 uv, bool srgb);

float srgb_to_linear(float v);
float linear_to_srgb(float v);

}  // namespace pathfarm
