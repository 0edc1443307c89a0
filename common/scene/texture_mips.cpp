// Box-filtered mip chains and the level a footprint asks for.
#include "common/scene/texture_mips.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "common/base/hash.h"
#include "common/scene/scene_model.h"

namespace pathfarm {
namespace {

// float(b) / 255, looked up (no division per channel and texel).
const std::array<float, 256>& unit_decode_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int b = 0; b < 256; ++b)
            t[std::size_t(b)] = float(b) / 255.0f;
        return t;
    }();
    return table;
}

uint8_t srgb_byte_by_formula(float linear) { return encode_unit_byte(linear_to_srgb(linear)); }

// thresholds[k] = the least float at which srgb_byte_by_formula reaches k + 1, found by
// bisection over the float bit patterns (they order as the values do for x >= 0), so counting
// the thresholds at or below x gives the formula's byte exactly (it is monotone), at eight
// comparisons instead of a powf per channel and texel.
const std::array<float, 255>& srgb_encode_thresholds() {
    static const std::array<float, 255> thresholds = [] {
        std::array<float, 255> t{};
        const uint32_t one = std::bit_cast<uint32_t>(1.0f);
        for (int k = 0; k < 255; ++k) {
            uint32_t lo = 0, hi = one;  // byte(lo) <= k < byte(hi) = 255 (for k < 255)
            while (hi - lo > 1) {
                const uint32_t mid = lo + (hi - lo) / 2;
                (srgb_byte_by_formula(std::bit_cast<float>(mid)) > k ? hi : lo) = mid;
            }
            t[std::size_t(k)] = std::bit_cast<float>(hi);
        }
        return t;
    }();
    return thresholds;
}

uint8_t encode_srgb_byte(float linear, const std::array<float, 255>& thresholds) {
    if (!(linear > 0.0f)) return 0;  // also NaN, as the formula's clamp
    int byte = 0;
    for (int step = 128; step > 0; step /= 2)  // thresholds ascend: a branch-free bisection
        byte +=
            (byte + step <= 255 && thresholds[std::size_t(byte + step - 1)] <= linear) ? step : 0;
    return uint8_t(byte);
}

// Source texels [first, last) that destination texel i of n covers along an axis of m.
struct Span {
    int first, last;
};
Span span(int i, int n, int m) { return {int(int64_t(i) * m / n), int(int64_t(i + 1) * m / n)}; }

}  // namespace

uint8_t encode_unit_byte(float v) {
    const float x = v > 0.0f ? std::min(v, 1.0f) * 255.0f : 0.0f;  // NaN too: 0
    const float whole = std::floor(x);
    return uint8_t(int(whole) + int(x - whole >= 0.5f));  // x - whole is exact for x >= 0
}

uint8_t encode_srgb_byte(float linear) {
    return encode_srgb_byte(linear, srgb_encode_thresholds());
}

Image downsample_image(const Image& source, bool srgb) {
    Image out;
    out.name = source.name;
    out.width = std::max(1, source.width / 2);
    out.height = std::max(1, source.height / 2);
    out.rgba.resize(std::size_t(out.width) * out.height * 4);
    const auto& unit = unit_decode_table();
    const auto& colour = srgb ? srgb_decode_table() : unit;
    const auto& thresholds = srgb_encode_thresholds();
    for (int y = 0; y < out.height; ++y) {
        const Span sy = span(y, out.height, source.height);
        for (int x = 0; x < out.width; ++x) {
            const Span sx = span(x, out.width, source.width);
            float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            for (int v = sy.first; v < sy.last; ++v)
                for (int u = sx.first; u < sx.last; ++u) {
                    const uint8_t* p = &source.rgba[(std::size_t(v) * source.width + u) * 4];
                    sum[0] += colour[p[0]];
                    sum[1] += colour[p[1]];
                    sum[2] += colour[p[2]];
                    sum[3] += unit[p[3]];
                }
            const float inv = 1.0f / float((sy.last - sy.first) * (sx.last - sx.first));
            uint8_t* q = &out.rgba[(std::size_t(y) * out.width + x) * 4];
            for (int c = 0; c < 3; ++c)
                q[c] = srgb ? encode_srgb_byte(sum[c] * inv, thresholds)
                            : encode_unit_byte(sum[c] * inv);
            q[3] = encode_unit_byte(sum[3] * inv);
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

TextureMips::Source TextureMips::source_of(const Image& image, uint8_t srgb) {
    return {image.width, image.height, hash_bytes_fast(image.rgba.data(), image.rgba.size()), srgb};
}

void TextureMips::build(const SceneModel& scene, std::size_t image, const Source& source) {
    std::vector<Image>& chain = chains_[image];
    chain.clear();
    const Image* level = &scene.images[image];
    sources_[image] = source;
    if (level->width <= 0 || level->height <= 0 ||
        level->rgba.size() != std::size_t(level->width) * std::size_t(level->height) * 4)
        return;  // a missing image samples white at every level
    while (level->width > 1 || level->height > 1) {
        chain.push_back(downsample_image(*level, srgb_[image] != 0));
        level = &chain.back();
    }
}

void TextureMips::rebuild(const SceneModel& scene) {
    std::vector<std::vector<Image>> before = std::move(chains_);
    const std::vector<Source> built_from = std::move(sources_);
    srgb_ = srgb_use(scene);
    chains_.assign(scene.images.size(), {});
    sources_.assign(scene.images.size(), {});
    std::vector<bool> taken(before.size(), false);
    for (std::size_t i = 0; i < scene.images.size(); ++i) {
        const Source wanted = source_of(scene.images[i], srgb_[i]);
        std::size_t j = 0;
        while (j < built_from.size() && (taken[j] || !(built_from[j] == wanted)))
            ++j;
        if (j == built_from.size()) {
            build(scene, i, wanted);
            continue;
        }
        taken[j] = true;
        chains_[i] = std::move(before[j]);
        sources_[i] = wanted;
    }
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
        if (stale[i]) build(scene, i, source_of(scene.images[i], srgb_[i]));
}

const std::vector<Image>& TextureMips::levels(int image) const {
    static const std::vector<Image> kNone;
    return image >= 0 && std::size_t(image) < chains_.size() ? chains_[std::size_t(image)] : kNone;
}

}  // namespace pathfarm
