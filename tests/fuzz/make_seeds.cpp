// Writes the seed corpora under tests/fuzz/corpus/<target>/ (committed; regenerate with
// `pathfarm-fuzz-seeds tests/fuzz/corpus` from a fuzz build): real messages from the real
// encoders, so the fuzzers start from inputs that pass the first checks, and small scene
// files of our own for the loaders (the shared scenes are never copied into the repository).
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/commit/commit_codec.h"
#include "common/film/first_hits.h"
#include "common/film/float_codec.h"
#include "common/net/auth.h"
#include "common/net/framing.h"
#include "common/net/handshake.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/scene_state.h"
#include "common/wire/messages.h"
#include "coordinator/http/web_protocol.h"

namespace pathfarm {
namespace {

namespace fs = std::filesystem;

void put(const fs::path& dir, const std::string& target, const std::string& name,
         const std::string& bytes) {
    fs::create_directories(dir / target);
    std::ofstream(dir / target / name, std::ios::binary) << bytes;
}

std::string be32(std::size_t n) { return {char(n >> 24), char(n >> 16), char(n >> 8), char(n)}; }

wire::Tile tile() {
    wire::Tile t{7, 7, 4, 6, {}, 0, 3.5, {120, 130}, {4000, 4100}, {}, 0.25};
    const std::vector<float> rgb(8 * 2 * 3, 0.5f);  // 8 pixels wide, 2 rows
    t.rgb_zstd = compress_floats(rgb.data(), rgb.size());
    t.raw_bytes = uint32_t(rgb.size() * sizeof(float));
    std::vector<FirstHit> hits(16);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        hits[i].distance = 1.0f + float(i);
        hits[i].instance = uint32_t(i % 3);
    }
    t.first_hits_zstd = encode_first_hits(hits.data(), hits.size());
    return t;
}

constexpr char kObj[] =
    "# a quad and a triangle\nmtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
    "vn 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl lamp\nf 1/1/1 2/2/1 3/3/1 4/4/1\n"
    "o tri\nf 1 2 5\n";
constexpr char kPlyAscii[] =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
// One triangle, its buffer inline as a data URI (base64 of 3 float3 positions + 3 u16 indices).
constexpr char kGltf[] = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
"nodes":[{"mesh":0,"translation":[0,0,-2]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},
"indices":1,"material":0}]}],"materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.2,0.2,1]},
"emissiveFactor":[1,1,1]}],"buffers":[{"byteLength":42,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIA"}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";

std::string ply_binary() {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
        "property float y\nproperty float z\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n";
    const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    s.append(reinterpret_cast<const char*>(v), sizeof(v));
    s.push_back(char(3));
    const int32_t f[3] = {0, 1, 2};
    s.append(reinterpret_cast<const char*>(f), sizeof(f));
    return s;
}

// The same triangle as a binary glTF: the JSON chunk (buffer without a URI) and a BIN chunk.
std::string glb() {
    std::string json = kGltf;
    const std::string uri_start = ",\"uri\":\"";
    const auto at = json.find(uri_start);
    json.erase(at, json.find('"', at + uri_start.size()) + 1 - at);
    while (json.size() % 4 != 0)
        json.push_back(' ');
    std::string bin(42, '\0');
    const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint16_t idx[3] = {0, 1, 2};
    std::memcpy(bin.data(), v, sizeof(v));
    std::memcpy(bin.data() + 36, idx, sizeof(idx));
    bin.resize(44, '\0');
    const auto le32 = [](uint32_t n) {
        return std::string{char(n), char(n >> 8), char(n >> 16), char(n >> 24)};
    };
    return "glTF" + le32(2) + le32(uint32_t(12 + 8 + json.size() + 8 + bin.size())) +
           le32(uint32_t(json.size())) + "JSON" + json + le32(uint32_t(bin.size())) +
           std::string("BIN\0", 4) + bin;
}

void write_all(const fs::path& dir) {
    unsigned char header[4];
    net::write_frame_header(1234, header);
    put(dir, "framing", "header_and_limit",
        std::string(reinterpret_cast<char*>(header), 4) + be32(1 << 16) + "payload");

    net::PeerInfo hello{net::PeerRole::tracer, "seed", "embree", 2, true, {1, 4}, 0, ""};
    put(dir, "handshake", "hello", net::hello_envelope(hello, net::make_nonce()));
    put(dir, "handshake", "challenge", net::challenge_envelope(net::make_nonce()));
    put(dir, "handshake", "proof", net::proof_envelope(std::string(32, 'm')));
    put(dir, "handshake", "welcome", net::welcome_envelope(9, std::string(32, 'w')));
    put(dir, "handshake", "error", net::error_envelope(net::ProtocolError::timeout, "late"));

    put(dir, "wire_tile", "tile_8_wide", std::string(1, char(7)) + wire::encode_tile(tile()));
    wire::Input input{3, 123456, std::nullopt, {0.1f, 0, 0.2f, 0.01f, 0}, true};
    put(dir, "wire_input", "move", wire::encode_input(input));
    input.camera_to_world = Mat4(1.0);
    put(dir, "wire_input", "pose", wire::encode_input(input));
    put(dir, "wire_frame", "jpeg",
        wire::encode_frame({5, 4, 2, wire::FrameCodec::jpeg, "\xff\xd8not-a-jpeg", 3}));

    auto scene = make_builtin_scene("cornell");
    if (!scene) throw std::runtime_error(scene.error().message);
    const Commit snapshot = make_snapshot(scene_state_from_model(*scene), 0);
    const EncodedCommit encoded = encode_commit(snapshot, 2048);
    int n = 0;
    for (const std::string& e : wire::encode_commit_envelopes(encoded))
        put(dir, "wire_tracer", "commit_part_" + std::to_string(n++), e);
    put(dir, "wire_tracer", "assignment",
        wire::encode_assignment({3, 3, 0, 8, 32, 16, 1, 9, 8, 0.5f, true, true}));
    put(dir, "wire_tracer", "truncation", wire::encode_truncation({3, 3, 4}));
    std::string commit(1, char(std::min<std::size_t>(encoded.chunks.size(), 3)));
    for (std::size_t i = 0; i < encoded.chunks.size() && i < 3; ++i)
        commit += be32(encoded.chunks[i].size()) + encoded.chunks[i];
    put(dir, "commit", "cornell_snapshot", commit + encoded.commit);

    coord::PlayerInput p;
    p.sequence = 11;
    p.move = {0.1f, 0.0f, -0.2f, 0.01f, 0.0f};
    p.action = true;
    put(dir, "web", "input", coord::encode_web_input(p));
    coord::WebFrameHeader h;
    h.width = 320;
    h.height = 180;
    put(dir, "web", "frame", coord::encode_web_frame(h, "picture"));

    put(dir, "obj", "quad_and_triangle.obj", kObj);
    put(dir, "ply", "quad_ascii.ply", kPlyAscii);
    put(dir, "ply", "triangle_binary.ply", ply_binary());
    put(dir, "gltf", "triangle.gltf", kGltf);
    put(dir, "glb", "triangle.glb", glb());
}

}  // namespace
}  // namespace pathfarm

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: pathfarm-fuzz-seeds OUT_DIR\n");
        return 2;
    }
    try {
        pathfarm::write_all(argv[1]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pathfarm-fuzz-seeds: %s\n", e.what());
        return 1;
    }
    return 0;
}
