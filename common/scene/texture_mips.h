// Mip-maps for texture lookups past a path's first hit (docs/rendering.md, "Texture level of
// detail"). A diffuse bounce sends the path anywhere, and its texel loads miss the cache; the
// path's estimate there is an average over a wide footprint anyway, so a coarser level of the
// texture (box-filtered, a few kilobytes) serves it. The camera's hit always reads level 0:
// the converged image's detail and the denoiser's albedo stay as they are.
#pragma once

#include <cstdint>
#include <vector>

#include "common/scene/texture.h"

namespace pathfarm {

struct SceneModel;

// Level l+1 of a chain from level l: floor-halved sizes (at least 1), each texel the box
// average of the source texels it covers (three columns or rows at an odd edge). With srgb the
// colour channels are averaged decoded, in linear light, and encoded again.
Image downsample_image(const Image& source, bool srgb);
// The bytes downsample_image writes: lround(clamp(v, 0, 1) * 255), and the sRGB byte of a
// linear value, equal to encode_unit_byte(linear_to_srgb(linear)) but found in a table of the
// byte boundaries instead of a powf (the chains of Sponza's 17 MB of texels).
uint8_t encode_unit_byte(float v);
uint8_t encode_srgb_byte(float linear);

// The level whose texels best match a footprint covering `texels` texels of level 0 (an
// area): floor(log2(texels) / 2), clamped to [0, max_level]. Integer steps, so both backends
// choose alike from alike floats.
int mip_level(float texels, int max_level);

// Per-image chains (levels 1..n; level 0 is the image itself), kept across frames: a backend
// rebuilds only the images whose texels or colour use changed.
class TextureMips {
public:
    // Every image's chain, taken over from the chains held before for images of the same size,
    // texels and colour use (a structural change, such as an object added, keeps most images:
    // Sponza's chains cost a scene build about 0.1 s), built for the others.
    void rebuild(const SceneModel& scene);
    // After a change that kept the scene's structure: rebuilds the chains of the images the
    // listed textures use, and of images whose colour use (sRGB or linear) changed.
    void update(const SceneModel& scene, const std::vector<uint32_t>& changed_textures);

    // Levels past 0 of `image` (empty when it has none or is unknown).
    const std::vector<Image>& levels(int image) const;
    // Whether an image's chain averages in linear light (a colour texture uses it).
    static std::vector<uint8_t> srgb_use(const SceneModel& scene);

private:
    // What a chain was built from: the image's size, a hash of its texels, its colour use.
    struct Source {
        int width = 0, height = 0;
        uint64_t texels = 0;
        uint8_t srgb = 0;
        bool operator==(const Source&) const = default;
    };
    static Source source_of(const Image& image, uint8_t srgb);
    // Builds `image`'s chain, which `source` describes (its hash computed once by the caller).
    void build(const SceneModel& scene, std::size_t image, const Source& source);

    std::vector<std::vector<Image>> chains_;  // by image index
    std::vector<uint8_t> srgb_;               // the colour use each chain was built for
    std::vector<Source> sources_;             // what each chain was built from
};

}  // namespace pathfarm
