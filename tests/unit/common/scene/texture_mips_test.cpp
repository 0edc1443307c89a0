// Mip chains and level choice (texture_mips.h) on random images of random sizes: every level
// halves its sizes down to one texel, averages in the light the texture is used in (sRGB
// colour averaged decoded), keeps a uniform image uniform at any size, and the level follows
// the footprint in powers of four. Rebuilds follow the changes they are told of.
#include "common/scene/texture_mips.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/render/shading_scene.h"
#include "common/scene/scene_model.h"

namespace pathfarm::texture_mips_test {
namespace {

Image random_image(std::mt19937& rng, int w, int h) {
    Image im{"random", w, h, std::vector<uint8_t>(std::size_t(w) * h * 4)};
    std::uniform_int_distribution<int> byte(0, 255);
    for (uint8_t& b : im.rgba)
        b = uint8_t(byte(rng));
    return im;
}

// Mean of channel c over the image, decoded from sRGB when asked.
double mean(const Image& im, int c, bool srgb) {
    double sum = 0.0;
    for (std::size_t i = 0; i < im.rgba.size(); i += 4) {
        const float v = float(im.rgba[i + std::size_t(c)]) / 255.0f;
        sum += srgb && c < 3 ? srgb_to_linear(v) : v;
    }
    return sum / double(im.rgba.size() / 4);
}

TEST(TextureMips, LevelsHalveDownToOneTexelForAnySize) {
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> size(1, 70);
    for (int trial = 0; trial < 40; ++trial) {
        const int w = size(rng), h = size(rng);
        SceneModel scene;
        scene.images.push_back(random_image(rng, w, h));
        TextureMips mips;
        mips.rebuild(scene);
        const std::vector<Image>& levels = mips.levels(0);
        int lw = w, lh = h;
        for (const Image& level : levels) {
            lw = std::max(1, lw / 2);
            lh = std::max(1, lh / 2);
            ASSERT_EQ(level.width, lw) << w << "x" << h;
            ASSERT_EQ(level.height, lh) << w << "x" << h;
            ASSERT_EQ(level.rgba.size(), std::size_t(lw) * lh * 4);
        }
        EXPECT_EQ(lw, 1) << w << "x" << h;
        EXPECT_EQ(lh, 1) << w << "x" << h;
        EXPECT_EQ(int(levels.size()), int(std::floor(std::log2(std::max(w, h)))));
    }
}

TEST(TextureMips, PowerOfTwoLevelsKeepTheMeanInTheirLight) {
    std::mt19937 rng(12);
    for (const bool srgb : {false, true}) {
        for (int trial = 0; trial < 8; ++trial) {
            const int w = 1 << std::uniform_int_distribution<int>(0, 6)(rng);
            const int h = 1 << std::uniform_int_distribution<int>(0, 6)(rng);
            const Image image = random_image(rng, w, h);
            const Image* level = &image;
            std::vector<Image> chain;
            chain.reserve(16);
            while (level->width > 1 || level->height > 1) {
                chain.push_back(downsample_image(*level, srgb));
                level = &chain.back();
                for (int c = 0; c < 4; ++c)  // 8-bit rounding per level, at most half a step
                    EXPECT_NEAR(mean(*level, c, srgb), mean(image, c, srgb),
                                double(chain.size()) * 0.6 / 255.0)
                        << w << "x" << h << " srgb " << srgb << " level " << chain.size();
            }
        }
    }
}

TEST(TextureMips, ColourIsAveragedInLinearLight) {
    // Black and white texels: their average light is 0.5, sRGB code 188, not code 128 (0.216).
    Image checker{
        "checker", 2, 2, {0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 255, 0, 0, 0, 255}};
    const Image srgb = downsample_image(checker, true);
    EXPECT_NEAR(srgb_to_linear(srgb.rgba[0] / 255.0f), 0.5f, 0.005f);
    const Image linear = downsample_image(checker, false);
    EXPECT_NEAR(linear.rgba[0] / 255.0f, 0.5f, 0.005f);
}

TEST(TextureMips, UniformImagesStayUniformAtOddSizes) {
    std::mt19937 rng(13);
    std::uniform_int_distribution<int> size(1, 41), byte(0, 255);
    for (int trial = 0; trial < 20; ++trial) {
        const int w = size(rng) | 1, h = size(rng) | 1;
        const uint8_t texel[4] = {uint8_t(byte(rng)), uint8_t(byte(rng)), uint8_t(byte(rng)),
                                  uint8_t(byte(rng))};
        Image im{"uniform", w, h, {}};
        for (int i = 0; i < w * h; ++i)
            im.rgba.insert(im.rgba.end(), texel, texel + 4);
        const Image half = downsample_image(im, trial % 2 == 0);
        for (std::size_t i = 0; i < half.rgba.size(); ++i)
            ASSERT_EQ(half.rgba[i], texel[i % 4]) << w << "x" << h;
    }
}

// The table-driven encodings against the formulas they replace, at random values and at every
// byte boundary of the sRGB curve, where a wrong threshold or an off-by-one would show.
TEST(TextureMips, ByteEncodingsEqualTheirFormulas) {
    const auto by_formula = [](float v) {
        return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
    };
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(-0.1f, 1.1f), exponent(-30.0f, 0.0f);
    std::vector<float> values;
    for (int i = 0; i < 200000; ++i) {
        values.push_back(unit(rng));
        values.push_back(std::exp2(exponent(rng)));  // small values, the curve's linear part
    }
    for (int k = 0; k < 255; ++k) {  // 64 floats either side of each boundary
        const double code = (k + 0.5) / 255.0;
        float x = float(code <= 0.04045 ? code / 12.92 : std::pow((code + 0.055) / 1.055, 2.4));
        for (int i = 0; i < 64; ++i)
            x = std::nextafter(x, 0.0f);
        for (int i = 0; i < 128; ++i, x = std::nextafter(x, 2.0f))
            values.push_back(x);
    }
    int wrong_srgb = 0, wrong_unit = 0;
    for (const float v : values) {
        wrong_srgb += encode_srgb_byte(v) != by_formula(linear_to_srgb(v));
        wrong_unit += encode_unit_byte(v) != by_formula(v);
        wrong_unit += encode_unit_byte(float(int(v * 255.0f)) / 255.0f + 0.5f / 255.0f) !=
                      by_formula(float(int(v * 255.0f)) / 255.0f + 0.5f / 255.0f);  // halves
    }
    EXPECT_EQ(wrong_srgb, 0) << "of " << values.size();
    EXPECT_EQ(wrong_unit, 0) << "of " << 2 * values.size();
    EXPECT_EQ(encode_srgb_byte(std::nanf("")), 0);
    EXPECT_EQ(encode_unit_byte(std::nanf("")), 0);
    EXPECT_EQ(encode_srgb_byte(1.0f), 255);
    EXPECT_EQ(encode_srgb_byte(5.0f), 255);
}

TEST(TextureMips, LevelFollowsTheFootprintInPowersOfFour) {
    EXPECT_EQ(mip_level(0.0f, 10), 0);
    EXPECT_EQ(mip_level(-5.0f, 10), 0);
    EXPECT_EQ(mip_level(std::nanf(""), 10), 0);
    EXPECT_EQ(mip_level(INFINITY, 10), 10);
    EXPECT_EQ(mip_level(1e6f, 0), 0);
    std::mt19937 rng(14);
    std::uniform_real_distribution<float> exponent(-4.0f, 40.0f);
    for (int i = 0; i < 1000; ++i) {
        const float texels = std::exp2(exponent(rng));
        const int level = mip_level(texels, 12);
        const int expected =
            texels < 4.0f ? 0 : std::min(12, int(std::floor(std::log2(texels))) / 2);
        ASSERT_EQ(level, expected) << texels;
        if (level > 0 && level < 12) {  // 4^l <= texels < 4^(l+1)
            EXPECT_LE(std::ldexp(1.0f, 2 * level), texels);
            EXPECT_LT(texels, std::ldexp(1.0f, 2 * level + 2));
        }
    }
}

// A one-quad scene whose base colour is a fine black and white checker.
SceneModel checker_quad(int size) {
    SceneModel scene;
    Image im{"checker", size, size, {}};
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const uint8_t v = (x + y) % 2 ? 255 : 0;
            im.rgba.insert(im.rgba.end(), {v, v, v, 255});
        }
    scene.images.push_back(std::move(im));
    Texture t;
    t.image = 0;
    t.sampler.filter = FilterMode::nearest;
    scene.textures.push_back(t);
    Material m;
    m.base_color_texture.texture = 0;
    scene.materials.push_back(m);
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    scene.meshes.push_back(mesh);
    scene.instances.push_back({0, -1, Mat4(1.0f), 0, false});
    return scene;
}

TEST(TextureMips, WideFootprintsReadTheAverageAndTheCameraHitReadsTexels) {
    const SceneModel scene = checker_quad(64);
    TextureMips mips;
    mips.rebuild(scene);
    const ShadingScene shading(scene, &mips);
    std::mt19937 rng(15);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    for (int i = 0; i < 200; ++i) {
        Hit hit;
        hit.instance = 0;
        hit.prim = i % 2;
        hit.u = u01(rng) * 0.5f;
        hit.v = u01(rng) * 0.5f;
        SurfacePoint sp = shading.surface(hit);
        EXPECT_NEAR(sp.uv_density, 1.0f, 1e-5f);
        SurfacePoint camera = sp;
        const float texel = shading.material_point(camera, 0.0f).base_color.x;
        EXPECT_TRUE(texel == 0.0f || texel == 1.0f) << texel;
        // The whole quad in the footprint: the top level, half the light.
        EXPECT_NEAR(shading.material_point(sp, 2.0f).base_color.x, 0.5f, 0.01f);
    }
    // Without mips every footprint reads level 0.
    const ShadingScene flat(scene);
    Hit hit;
    hit.u = hit.v = 0.25f;
    SurfacePoint sp = flat.surface(hit);
    const float texel = flat.material_point(sp, 2.0f).base_color.x;
    EXPECT_TRUE(texel == 0.0f || texel == 1.0f) << texel;
}

TEST(TextureMips, UpdateRebuildsChangedImagesAndColourUse) {
    SceneModel scene = checker_quad(8);
    scene.materials[0].base_color_texture.texture = -1;
    scene.materials[0].normal_texture.texture = 0;  // linear use
    TextureMips mips;
    mips.rebuild(scene);
    EXPECT_NEAR(mips.levels(0).back().rgba[0] / 255.0f, 0.5f, 0.005f);
    // Now a colour texture: averaged in linear light, encoded as sRGB.
    scene.materials[0].base_color_texture.texture = 0;
    mips.update(scene, {});
    EXPECT_NEAR(srgb_to_linear(mips.levels(0).back().rgba[0] / 255.0f), 0.5f, 0.005f);
    // New texels: rebuilt when their texture is named, kept otherwise (the caller's contract).
    std::fill(scene.images[0].rgba.begin(), scene.images[0].rgba.end(), uint8_t(255));
    mips.update(scene, {});
    EXPECT_LT(mips.levels(0).back().rgba[0], 255);
    mips.update(scene, {0});
    EXPECT_EQ(mips.levels(0).back().rgba[0], 255);
    // A scene with more images than the chains were built for is rebuilt whole.
    scene.images.push_back(scene.images[0]);
    mips.update(scene, {});
    EXPECT_EQ(mips.levels(1).size(), 3u);
    EXPECT_TRUE(mips.levels(7).empty());
}

}  // namespace
}  // namespace pathfarm::texture_mips_test

namespace pathfarm::texture_mips_test {
namespace {

// A rebuild after a structural change takes over the chains of images it has seen (same size,
// texels and colour use), wherever they moved, and builds the rest; either way every chain is
// what a fresh build gives.
TEST(TextureMips, RebuildKeepsTheChainsOfUnchangedImagesOnly) {
    std::mt19937 rng(23);
    SceneModel scene = checker_quad(8);
    scene.images.clear();
    for (int i = 0; i < 4; ++i)
        scene.images.push_back(random_image(rng, 5 + i, 9 - i));
    scene.textures = {Texture{0, {}}, Texture{1, {}}, Texture{2, {}}, Texture{3, {}}};
    scene.materials[0].base_color_texture.texture = 0;  // image 0 in sRGB, the rest linear
    TextureMips mips;
    mips.rebuild(scene);
    std::vector<const uint8_t*> kept;
    for (int i = 0; i < 4; ++i)
        kept.push_back(mips.levels(i)[0].rgba.data());
    // Images 0 and 1 swap places, image 2 gets one texel changed, image 3 turns colour.
    std::swap(scene.images[0], scene.images[1]);
    scene.images[2].rgba[5] ^= 0x40;
    scene.textures = {Texture{0, {}}, Texture{1, {}}, Texture{2, {}}, Texture{3, {}}};
    scene.materials[0].base_color_texture.texture = 1;  // the old image 0, still sRGB
    scene.materials[0].emissive_texture.texture = 3;    // image 3 now sRGB
    mips.rebuild(scene);
    EXPECT_EQ(mips.levels(1)[0].rgba.data(), kept[0]) << "moved, same use: taken over";
    EXPECT_EQ(mips.levels(0)[0].rgba.data(), kept[1]);
    TextureMips fresh;
    fresh.rebuild(scene);
    for (int i = 0; i < 4; ++i) {
        ASSERT_EQ(mips.levels(i).size(), fresh.levels(i).size()) << "image " << i;
        for (std::size_t l = 0; l < fresh.levels(i).size(); ++l)
            EXPECT_EQ(mips.levels(i)[l].rgba, fresh.levels(i)[l].rgba)
                << "image " << i << " level " << l + 1;
    }
    EXPECT_NE(mips.levels(2)[0].rgba.data(), kept[2]) << "new texels: built anew";
    EXPECT_NE(mips.levels(3)[0].rgba.data(), kept[3]) << "new colour use: built anew";
}

}  // namespace
}  // namespace pathfarm::texture_mips_test
