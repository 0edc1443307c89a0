// Scene loading: real shared scenes load with the expected content; malformed, truncated and
// damaged files give a one-line error naming the file, or are repaired with a warning.
#include "common/scene/load/scene_loader.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <zlib.h>

#include "common/scene/load/file_read.h"
#include "tests/support/test_env.h"

namespace pathfarm::loader_test {
namespace {

void write_file(const std::string& path, const std::string& data) {
    std::ofstream(path, std::ios::binary) << data;
}

std::string read_prefix(const std::string& path, std::size_t bytes) {
    std::ifstream in(path, std::ios::binary);
    std::string data(bytes, '\0');
    in.read(data.data(), std::streamsize(bytes));
    data.resize(std::size_t(in.gcount()));
    return data;
}

void expect_error_naming(const Result<SceneModel>& r, const std::string& path) {
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(path), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << "one line: " << r.error().message;
}

TEST(SceneLoader, BuiltinCornellHasEightInstancesAndALight) {
    auto s = load_scene("builtin:cornell");
    ASSERT_TRUE(s.ok());
    EXPECT_EQ(s->instances.size(), 8u);
    EXPECT_EQ(triangle_count(*s), 36u);
    EXPECT_TRUE(has_emissive_triangles(*s));
    EXPECT_FALSE(uses_sun_sky(*s));
}

TEST(SceneLoader, BuiltinDefaultHasWhatTheDemoNeeds) {
    auto s = load_scene("builtin:default");
    ASSERT_TRUE(s.ok());
    std::vector<int> uses(s->meshes.size(), 0);
    int instanced = 0, lights = 0;
    for (const Instance& i : s->instances)
        ++uses[i.mesh];
    for (const Instance& i : s->instances) {
        instanced += uses[i.mesh] > 1;
        lights += s->materials[s->meshes[i.mesh].material].is_emissive();
    }
    EXPECT_GE(instanced, 8);
    EXPECT_GE(lights, 3);
    EXPECT_TRUE(uses_sun_sky(*s));
    EXPECT_FALSE(s->textures.empty());
}

TEST(SceneLoader, UnknownBuiltinAndMissingFileAreErrors) {
    expect_error_naming(load_scene("builtin:nope"), "builtin:nope");
    expect_error_naming(load_scene("/no/such/scene.gltf"), "/no/such/scene.gltf");
    const std::string dir = test::scratch_dir();
    write_file(dir + "/x.fbx", "data");
    expect_error_naming(load_scene(dir + "/x.fbx"), dir + "/x.fbx");
    // A directory (a scene's folder instead of its file) is named as one, not as missing.
    std::filesystem::create_directories(dir + "/scene.gltf");
    const auto folder = load_scene(dir + "/scene.gltf");
    ASSERT_FALSE(folder.ok());
    EXPECT_NE(folder.error().message.find("a directory"), std::string::npos)
        << folder.error().message;
}

TEST(SceneLoader, LoadsSharedObjPlyAndGltfScenes) {
    PF_REQUIRE_SCENES(scenes);
    auto cornell = load_scene(scenes + "/cornell-box/CornellBox-Original.obj");
    ASSERT_TRUE(cornell.ok()) << cornell.error().message;
    EXPECT_EQ(triangle_count(*cornell), 36u);
    EXPECT_TRUE(has_emissive_triangles(*cornell));

    auto bunny = load_scene(scenes + "/stanford-bunny/bun_zipper_res4.ply");
    ASSERT_TRUE(bunny.ok()) << bunny.error().message;
    EXPECT_EQ(triangle_count(*bunny), 948u);

    auto armadillo = load_scene(
        scenes + "/stanford-armadillo/Armadillo.ply.gz");  // binary big-endian + extra property
    ASSERT_TRUE(armadillo.ok()) << armadillo.error().message;
    EXPECT_EQ(triangle_count(*armadillo), 345944u);

    auto helmet = load_scene(scenes + "/damaged-helmet/DamagedHelmet.gltf");
    ASSERT_TRUE(helmet.ok()) << helmet.error().message;
    EXPECT_EQ(triangle_count(*helmet), 15452u);
    ASSERT_EQ(helmet->materials.size(), 1u);
    EXPECT_TRUE(helmet->materials[0].normal_texture.valid());
    EXPECT_GT(helmet->images.at(0).width, 0);
    EXPECT_FALSE(helmet->meshes[0].tangents.empty());

    auto fox = load_scene(scenes + "/fox/Fox.glb");
    ASSERT_TRUE(fox.ok()) << fox.error().message;
    EXPECT_EQ(triangle_count(*fox), 576u);
}

TEST(SceneLoader, GltfExtensionsAreHonoured) {
    PF_REQUIRE_SCENES(scenes);
    // The barn lamp: transmission + volume + emissive_strength, and KTX2 textures that cannot be
    // decoded: they cost their textures with a warning, not the scene.
    auto lamp = load_scene(scenes + "/anisotropy-barn-lamp/AnisotropyBarnLamp.gltf");
    ASSERT_TRUE(lamp.ok()) << lamp.error().message;
    bool transmissive = false, strong_emitter = false;
    for (const Material& m : lamp->materials) {
        transmissive |= m.transmission_factor == 1.0f;
        strong_emitter |= m.emissive_strength == 25.0f && m.emission() == Rgb(25.0f, 12.5f, 6.25f);
        EXPECT_FALSE(std::isfinite(m.attenuation_distance)) << "no attenuationDistance means none";
    }
    EXPECT_TRUE(transmissive);
    EXPECT_TRUE(strong_emitter);
    int undecoded = 0;
    for (const Texture& t : lamp->textures)
        undecoded += t.image < 0;
    EXPECT_GE(undecoded, 1);
}

TEST(SceneLoader, GltfVolumeIorSpecularAndCamera) {
    const std::string dir = test::scratch_dir();
    const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    write_file(dir + "/tri.bin", std::string(reinterpret_cast<const char*>(tri), sizeof(tri)));
    write_file(dir + "/tri.gltf", R"({"asset":{"version":"2.0"},
      "extensionsUsed":["KHR_materials_volume","KHR_materials_ior","KHR_materials_specular","KHR_materials_transmission"],
      "buffers":[{"uri":"tri.bin","byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
      "materials":[{"pbrMetallicRoughness":{"metallicFactor":0,"roughnessFactor":0.25},"extensions":{
        "KHR_materials_transmission":{"transmissionFactor":0.75},"KHR_materials_ior":{"ior":1.33},
        "KHR_materials_specular":{"specularFactor":0.0,"specularColorFactor":[1,0.5,0.25]},
        "KHR_materials_volume":{"attenuationDistance":0.2,"attenuationColor":[0.5,0.6,0.7]}}}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
      "cameras":[{"type":"perspective","perspective":{"yfov":0.5,"znear":0.01}}],
      "nodes":[{"mesh":0,"translation":[1,2,3]},{"camera":0,"translation":[0,0,5]}],"scenes":[{"nodes":[0,1]}]})");
    auto s = load_scene(dir + "/tri.gltf");
    ASSERT_TRUE(s.ok()) << s.error().message;
    const Material& m = s->materials.at(0);
    EXPECT_EQ(m.transmission_factor, 0.75f);
    EXPECT_EQ(m.ior, 1.33f);
    EXPECT_EQ(m.specular_factor, 0.0f);
    EXPECT_EQ(m.specular_color_factor, Rgb(1.0f, 0.5f, 0.25f));
    EXPECT_EQ(m.attenuation_distance, 0.2f);
    EXPECT_EQ(m.attenuation_color, Rgb(0.5f, 0.6f, 0.7f));
    EXPECT_TRUE(s->meshes[0].normals.empty()) << "no NORMAL: flat shading";
    ASSERT_EQ(s->cameras.size(), 1u);
    EXPECT_EQ(s->cameras[0].yfov_radians, 0.5f);
    EXPECT_EQ(Vec3(s->cameras[0].camera_to_world[3]), Vec3(0, 0, 5));
    EXPECT_EQ(Vec3(s->instances[0].transform[3]), Vec3(1, 2, 3));
}

TEST(SceneLoader, GltfAlphaModesAndTextureTransforms) {
    const std::string dir = test::scratch_dir();
    const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    write_file(dir + "/tri.bin", std::string(reinterpret_cast<const char*>(tri), sizeof(tri)));
    write_file(dir + "/alpha.gltf",
               R"({"asset":{"version":"2.0"},"extensionsUsed":["KHR_texture_transform"],
      "buffers":[{"uri":"tri.bin","byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
      "images":[{"uri":"missing.png"}],"textures":[{"source":0}],
      "materials":[{"alphaMode":"MASK","alphaCutoff":0.25,"pbrMetallicRoughness":{"baseColorTexture":{"index":0,
          "extensions":{"KHR_texture_transform":{"offset":[0.5,0.25],"rotation":1.5,"scale":[2,3]}}}}},
        {"alphaMode":"MASK"},{"alphaMode":"BLEND","normalTexture":{"index":0,
          "extensions":{"KHR_texture_transform":{"scale":[4,4]}}}},{"alphaMode":"OPAQUE"},{}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
      "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})");
    auto s = load_scene(dir + "/alpha.gltf");
    ASSERT_TRUE(s.ok()) << s.error().message;
    ASSERT_EQ(s->materials.size(), 5u);
    const Material& mask = s->materials[0];
    EXPECT_EQ(mask.alpha_mode, AlphaMode::mask);
    EXPECT_EQ(mask.alpha_cutoff, 0.25f);
    EXPECT_EQ(mask.base_color_texture.transform.offset, Vec2(0.5f, 0.25f));
    EXPECT_EQ(mask.base_color_texture.transform.rotation, 1.5f);
    EXPECT_EQ(mask.base_color_texture.transform.scale, Vec2(2.0f, 3.0f));
    EXPECT_EQ(s->materials[1].alpha_mode, AlphaMode::mask);
    EXPECT_EQ(s->materials[1].alpha_cutoff, 0.5f) << "glTF's default cutoff";
    EXPECT_EQ(s->materials[2].alpha_mode, AlphaMode::blend);
    EXPECT_EQ(s->materials[2].normal_texture.transform.scale, Vec2(4.0f));
    EXPECT_TRUE(s->materials[2].base_color_texture.transform.identity());
    EXPECT_EQ(s->materials[3].alpha_mode, AlphaMode::opaque);
    EXPECT_EQ(s->materials[4].alpha_mode, AlphaMode::opaque);
    EXPECT_FALSE(s->materials[3].alpha_tested());
    EXPECT_TRUE(mask.alpha_tested());
}

TEST(SceneLoader, TruncatedAndCorruptFilesAreErrors) {
    PF_REQUIRE_SCENES(scenes);
    const std::string dir = test::scratch_dir();
    const std::string glb = dir + "/fox-truncated.glb";
    write_file(glb, read_prefix(scenes + "/fox/Fox.glb", 50000));
    expect_error_naming(load_scene(glb), glb);

    const std::string gz = dir + "/armadillo-truncated.ply.gz";
    write_file(gz, read_prefix(scenes + "/stanford-armadillo/Armadillo.ply.gz", 200000));
    expect_error_naming(load_scene(gz), gz);

    const std::string json = dir + "/broken.gltf";
    write_file(json, "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [ {");
    expect_error_naming(load_scene(json), json);

    const std::string bad_bin = dir + "/short-buffer.gltf";
    write_file(dir + "/short.bin", std::string(12, '\0'));
    write_file(bad_bin,
               R"({"asset":{"version":"2.0"},"buffers":[{"uri":"short.bin","byteLength":12}],
      "bufferViews":[{"buffer":0,"byteLength":12}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})");
    expect_error_naming(load_scene(bad_bin), bad_bin);
}

TEST(SceneLoader, PlyAsciiAndBinaryAgree) {
    const std::string dir = test::scratch_dir();
    const std::string header =
        "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty uchar intensity\nproperty list uchar int "
        "vertex_indices\nend_header\n";
    write_file(dir + "/quad.ply",
               "ply\nformat ascii 1.0\n" + header + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n7 4 0 1 2 3\n");
    std::string bin = "ply\nformat binary_big_endian 1.0\n" + header;
    const auto put_be = [&](const void* p, int n) {
        for (int i = n - 1; i >= 0; --i)
            bin.push_back(static_cast<const char*>(p)[i]);
    };
    const float v[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    for (float f : v)
        put_be(&f, 4);
    bin.push_back(7);
    bin.push_back(4);
    for (int32_t i : {0, 1, 2, 3})
        put_be(&i, 4);
    write_file(dir + "/quad_be.ply", bin);
    auto a = load_scene(dir + "/quad.ply");
    auto b = load_scene(dir + "/quad_be.ply");
    ASSERT_TRUE(a.ok()) << a.error().message;
    ASSERT_TRUE(b.ok()) << b.error().message;
    EXPECT_EQ(a->meshes[0].indices, b->meshes[0].indices);
    EXPECT_EQ(a->meshes[0].positions, b->meshes[0].positions);
    EXPECT_EQ(triangle_count(*a), 2u);
    write_file(dir + "/short.ply", bin.substr(0, bin.size() - 6));
    expect_error_naming(load_scene(dir + "/short.ply"), dir + "/short.ply");
}

TEST(SceneLoader, NanAndDegenerateTrianglesAreDropped) {
    const std::string dir = test::scratch_dir();
    write_file(dir + "/bad.obj",
               "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nv 2 0 0\n"
               "f 1 2 3\nf 1 2 4\nf 1 2 5\n");
    auto s = load_scene(dir + "/bad.obj");
    ASSERT_TRUE(s.ok()) << s.error().message;
    EXPECT_EQ(triangle_count(*s), 1u);
    write_file(dir + "/range.obj", "v 0 0 0\nv 1 0 0\nf 1 2 9\n");
    expect_error_naming(load_scene(dir + "/range.obj"), dir + "/range.obj");
}

TEST(FileRead, GzipAndPlainReadTheSame) {
    const std::string dir = test::scratch_dir();
    const std::string text = "hello pathfarm\n";
    write_file(dir + "/plain.txt", text);
    gzFile gz = gzopen((dir + "/packed.gz").c_str(), "wb");
    gzwrite(gz, text.data(), unsigned(text.size()));
    gzclose(gz);
    EXPECT_EQ(*read_file_maybe_gzip(dir + "/plain.txt"), text);
    EXPECT_EQ(*read_file_maybe_gzip(dir + "/packed.gz"), text);
}

}  // namespace
}  // namespace pathfarm::loader_test
