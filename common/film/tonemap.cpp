// ACES-fitted tonemapping to 8-bit sRGB.
#include "common/film/tonemap.h"

#include <algorithm>
#include <cmath>

namespace pathfarm {
namespace {

float aces_fit(float x) {
    x = std::max(x, 0.0f);
    return std::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

float encode_srgb(float v) {
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

}  // namespace

std::vector<uint8_t> tonemap_to_srgb8(const FloatImage& image, float exposure) {
    std::vector<uint8_t> out(image.rgb.size());
    for (std::size_t i = 0; i < image.rgb.size(); ++i) {
        const float v = std::isfinite(image.rgb[i]) ? image.rgb[i] * exposure : 0.0f;
        out[i] = uint8_t(std::lround(255.0f * encode_srgb(aces_fit(v))));
    }
    return out;
}

}  // namespace pathfarm
