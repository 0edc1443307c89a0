// Texture filtering with glTF wrap modes and sRGB decoding.
#include "common/scene/texture.h"

#include <array>
#include <cmath>

namespace pathfarm {

const std::array<float, 256>& srgb_decode_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i)
            t[std::size_t(i)] = srgb_to_linear(float(i) / 255.0f);
        return t;
    }();
    return table;
}

namespace {

int wrap_index(int i, int n, WrapMode mode) {
    switch (mode) {
        case WrapMode::clamp_to_edge:
            return std::clamp(i, 0, n - 1);
        case WrapMode::mirrored_repeat: {
            const int period = 2 * n;
            int m = i % period;
            if (m < 0) m += period;
            return m < n ? m : period - 1 - m;
        }
        case WrapMode::repeat:
        default: {
            int m = i % n;
            return m < 0 ? m + n : m;
        }
    }
}

Vec4 texel(const Image& image, int x, int y, bool srgb) {
    const uint8_t* p = &image.rgba[(std::size_t(y) * image.width + x) * 4];
    if (srgb) {
        const auto& t = srgb_decode_table();
        return {t[p[0]], t[p[1]], t[p[2]], p[3] / 255.0f};
    }
    return Vec4(p[0], p[1], p[2], p[3]) * (1.0f / 255.0f);
}

}  // namespace

float srgb_to_linear(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float v) {
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

Vec4 sample_image(const Image* image, const Sampler& sampler, Vec2 uv, bool srgb) {
    if (image == nullptr || image->width <= 0 || image->height <= 0 || !std::isfinite(uv.x) ||
        !std::isfinite(uv.y))
        return Vec4(1.0f);
    const int w = image->width;
    const int h = image->height;
    // Keep the coordinate in a range where float->int is exact; wrapping makes this lossless
    // for repeat and the clamp lossless for clamp_to_edge.
    const float fx = std::clamp(uv.x * float(w), -1e7f, 1e7f);
    const float fy = std::clamp(uv.y * float(h), -1e7f, 1e7f);
    if (sampler.filter == FilterMode::nearest) {
        const int x = wrap_index(int(std::floor(fx)), w, sampler.wrap_s);
        const int y = wrap_index(int(std::floor(fy)), h, sampler.wrap_t);
        return texel(*image, x, y, srgb);
    }
    const float px = fx - 0.5f;
    const float py = fy - 0.5f;
    const int x0 = int(std::floor(px));
    const int y0 = int(std::floor(py));
    const float tx = px - float(x0);
    const float ty = py - float(y0);
    const int xa = wrap_index(x0, w, sampler.wrap_s);
    const int xb = wrap_index(x0 + 1, w, sampler.wrap_s);
    const int ya = wrap_index(y0, h, sampler.wrap_t);
    const int yb = wrap_index(y0 + 1, h, sampler.wrap_t);
    const Vec4 top = glm::mix(texel(*image, xa, ya, srgb), texel(*image, xb, ya, srgb), tx);
    const Vec4 bottom = glm::mix(texel(*image, xa, yb, srgb), texel(*image, xb, yb, srgb), tx);
    return glm::mix(top, bottom, ty);
}

}  // namespace pathfarm
