// Box-filtered mip chains and the level a footprint asks for.
#include "common/scene/texture_mips.h"

#include <algorithm>
#include <cmath>

#include "common/scene/scene_model.h"

namespace pathfarm {
namespace {

uint8_t to_byte(float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

// Source texels [first, last) that destination texel i of n covers along an axis of m.
struct Span {
    int first, last;
};
Span span(int i, int n, int m) { return {int(int64_t(i) * m / n), int(int64_t(i + 1) * m / n)}; }

}  // namespace

Image downsample_image(const Image& source, bool srgb) {
    Image out;
    out.name = source.name;
    out.width = std::max(1, source.width / 2);
    out.height = std::max(1, source.height / 2);
    out.rgba.resize(std::size_t(out.width) * out.height * 4);
    const auto& decode = srgb_decode_table();
    for (int y = 0; y < out.height; ++y) {
        const Span sy = span(y, out.height, source.height);
        for (int x = 0; x < out.width; ++x) {
            const Span sx = span(x, out.width, source.width);
            float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            for (int v = sy.first; v < sy.last; ++v)
                for (int u = sx.first; u < sx.last; ++u) {
                    const uint8_t* p = &source.rgba[(std::size_t(v) * source.width + u) * 4];
                    for (int c = 0; c < 3; ++c)
                        sum[c] += srgb ? decode[p[c]] : float(p[c]) / 255.0f;
                    sum[3] += float(p[3]) / 255.0f;
                }
            const float inv = 1.0f / float((sy.last - sy.first) * (sx.last - sx.first));
            uint8_t* q = &out.rgba[(std::size_t(y) * out.width + x) * 4];
            for (int c = 0; c < 3; ++c)
                q[c] = to_byte(srgb ? linear_to_srgb(sum[c] * inv) : sum[c] * inv);
            q[3] = to_byte(sum[3] * inv);
        }
    }
    return out;
}

int mip_level(float texels, int max_level) {
    if (!(texels >= 4.0f) || max_level <= 0) return 0;  // also NaN
    if (texels > 1e30f) return max_level;
    return std::min(max_level, std::ilogb(texels) / 2);
}

std::vector<uint8_t> TextureMips::srgb_use(const SceneModel& scene) {
    std::vector<uint8_t> srgb(scene.images.size(), 0);
    for (const Material& m : scene.materials)
        for (const TextureRef* ref : {&m.base_color_texture, &m.emissive_texture})
            if (ref->valid() && std::size_t(ref->texture) < scene.textures.size()) {
                const int image = scene.textures[std::size_t(ref->texture)].image;
                if (image >= 0 && std::size_t(image) < srgb.size()) srgb[std::size_t(image)] = 1;
            }
    return srgb;
}

void TextureMips::build(const SceneModel& scene, std::size_t image) {
    std::vector<Image>& chain = chains_[image];
    chain.clear();
    const Image* level = &scene.images[image];
    if (level->width <= 0 || level->height <= 0 ||
        level->rgba.size() != std::size_t(level->width) * std::size_t(level->height) * 4)
        return;  // a missing image samples white at every level
    while (level->width > 1 || level->height > 1) {
        chain.push_back(downsample_image(*level, srgb_[image] != 0));
        level = &chain.back();
    }
}

void TextureMips::rebuild(const SceneModel& scene) {
    srgb_ = srgb_use(scene);
    chains_.assign(scene.images.size(), {});
    for (std::size_t i = 0; i < scene.images.size(); ++i)
        build(scene, i);
}

void TextureMips::update(const SceneModel& scene, const std::vector<uint32_t>& changed_textures) {
    if (chains_.size() != scene.images.size()) return rebuild(scene);
    const std::vector<uint8_t> srgb = srgb_use(scene);
    std::vector<uint8_t> stale(scene.images.size(), 0);
    for (std::size_t i = 0; i < srgb.size(); ++i)
        stale[i] = srgb[i] != srgb_[i];
    for (const uint32_t t : changed_textures)
        if (t < scene.textures.size()) {
            const int image = scene.textures[t].image;
            if (image >= 0 && std::size_t(image) < stale.size()) stale[std::size_t(image)] = 1;
        }
    srgb_ = srgb;
    for (std::size_t i = 0; i < stale.size(); ++i)
        if (stale[i]) build(scene, i);
}

const std::vector<Image>& TextureMips::levels(int image) const {
    static const std::vector<Image> kNone;
    return image >= 0 && std::size_t(image) < chains_.size() ? chains_[std::size_t(image)] : kNone;
}

}  // namespace pathfarm
