// The protobuf side of the commit codec, shared by its .cpp files and common/wire's. Include
// only from .cpp files (the layering check enforces it): it brings in commit.pb.h.
#pragma once

#include <bit>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/commit/commit.h"
#include "common/commit/commit_codec.h"
#include "pathfarm/wire/v1/commit.pb.h"

namespace pathfarm {

namespace commit_pb = ::pathfarm::wire::v1;
static_assert(std::endian::native == std::endian::little, "wire arrays are little endian");

struct ParsedCommit {
    commit_pb::Commit message;
};
struct ParsedChunk {
    commit_pb::BulkChunk message;
};

namespace codec {

// --- arrays as raw little-endian bytes
template <typename T>
std::string to_bytes(const std::vector<T>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}
template <typename T>
Status from_bytes(const std::string& bytes, std::vector<T>& out, const char* field) {
    if (bytes.size() % sizeof(T) != 0)
        return make_error(ErrorCode::parse_error, "{}: {} bytes, not a multiple of {}", field,
                          bytes.size(), sizeof(T));
    out.resize(bytes.size() / sizeof(T));
    if (!bytes.empty()) std::memcpy(out.data(), bytes.data(), bytes.size());
    return {};
}

// --- bulk payloads: serialised messages cut into BulkChunk messages
class BlobWriter {
public:
    BlobWriter(uint64_t frame, std::size_t max_chunk);
    uint64_t add(const google::protobuf::MessageLite& message);  // the blob's id (1, 2, ...)
    uint32_t count() const { return uint32_t(count_); }
    std::vector<std::string> take() { return std::move(chunks_); }

private:
    uint64_t frame_;
    std::size_t max_chunk_;
    uint64_t count_ = 0;
    std::vector<std::string> chunks_;
};
using Blobs = std::map<uint64_t, std::string>;  // id -> the blob's bytes

template <typename Payload>
Status parse_blob(const Blobs& blobs, uint64_t id, Payload& out) {
    const auto it = blobs.find(id);
    if (it == blobs.end())
        return make_error(ErrorCode::parse_error, "blob {} is not in the commit", id);
    if (!out.ParseFromString(it->second))
        return make_error(ErrorCode::parse_error, "blob {} is malformed", id);
    return {};
}

// The one inline-or-blob choice: payloads up to kInlineVertexBytes travel in the op.
template <typename Op, typename Payload>
void put_inline_or_blob(Op* op, Payload payload, BlobWriter& blobs) {
    if (payload.ByteSizeLong() > kInlineVertexBytes)
        op->set_blob(blobs.add(payload));
    else
        *op->mutable_inline_data() = std::move(payload);
}
template <typename Op, typename Payload>
Status get_inline_or_blob(const Op& op, const Blobs& blobs, Payload& out) {
    if (op.blob() == 0) {
        out = op.inline_data();
        return {};
    }
    return parse_blob(blobs, op.blob(), out);
}

// --- field codecs (field_codec.cpp), each encode beside its decode
std::string mat_bytes(const Mat4& m);
Status mat_from(const std::string& bytes, Mat4& m, const char* field);
void put_material(commit_pb::MaterialData* d, const Material& m);
Status get_material(const commit_pb::MaterialData& d, Material& m);
commit_pb::MeshData mesh_data(const Mesh& m);
Status get_mesh(const commit_pb::MeshData& d, Mesh& m);
commit_pb::ImageData image_data(const Image& image);
Status get_image(const commit_pb::ImageData& d, Image& image);
void put_texture(commit_pb::TextureData* d, const Texture& t);
Status get_texture(const commit_pb::TextureData& d, Texture& t);
void put_camera(commit_pb::CameraData* d, const Camera& c);
Status get_camera(const commit_pb::CameraData& d, Camera& c);
void put_environment(commit_pb::EnvironmentData* d, const Environment& e);
Status get_environment(const commit_pb::EnvironmentData& d, Environment& e);
void put_settings(commit_pb::SettingsData* d, const RenderSettings& s);
RenderSettings get_settings(const commit_pb::SettingsData& d);

// --- op codecs (op_codec.cpp)
void encode_op(const CommitOp& op, commit_pb::CommitOp& out, BlobWriter& blobs);
// Decodes one op; on failure `name` is the op's kind for the caller's message.
Status decode_op(const commit_pb::CommitOp& w, const Blobs& blobs, CommitOp& out,
                 const char*& name);

}  // namespace codec
}  // namespace pathfarm
