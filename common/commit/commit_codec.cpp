// Commit <-> protobuf: the commit header, its ops (op_codec.cpp) and its blobs.
#include "common/commit/commit_codec.h"

#include "common/commit/codec_internal.h"

namespace pathfarm {
namespace codec {

BlobWriter::BlobWriter(uint64_t frame, std::size_t max_chunk)
    : frame_(frame), max_chunk_(std::max<std::size_t>(max_chunk, 1)) {}

uint64_t BlobWriter::add(const google::protobuf::MessageLite& message) {
    const uint64_t id = ++count_;
    const std::string bytes = message.SerializeAsString();
    std::size_t offset = 0;
    do {
        commit_pb::BulkChunk chunk;
        chunk.set_frame(frame_);
        chunk.set_blob(id);
        chunk.set_offset(offset);
        chunk.set_total_bytes(bytes.size());
        const std::size_t n = std::min(max_chunk_, bytes.size() - offset);
        chunk.set_data(bytes.substr(offset, n));
        chunks_.push_back(chunk.SerializeAsString());
        offset += n;
    } while (offset < bytes.size());
    return id;
}

}  // namespace codec

namespace {

// Reassembles blobs from their chunks: each must arrive whole, in order, with one total size.
Result<codec::Blobs> assemble_blobs(const std::vector<const commit_pb::BulkChunk*>& chunks,
                                    uint64_t frame, uint32_t blob_count) {
    codec::Blobs blobs;
    std::map<uint64_t, uint64_t> totals;
    for (const commit_pb::BulkChunk* c : chunks) {
        if (c->frame() != frame || c->blob() == 0 || c->blob() > blob_count)
            return make_error(ErrorCode::parse_error,
                              "commit {}: chunk of blob {} (frame {}) does not belong here", frame,
                              c->blob(), c->frame());
        std::string& blob = blobs[c->blob()];
        const auto [it, first] = totals.emplace(c->blob(), c->total_bytes());
        if (c->offset() != blob.size() || it->second != c->total_bytes() ||
            blob.size() + c->data().size() > c->total_bytes())
            return make_error(ErrorCode::parse_error,
                              "commit {}: blob {} chunk out of order or oversized", frame,
                              c->blob());
        blob += c->data();
    }
    if (blobs.size() != blob_count)
        return make_error(ErrorCode::parse_error, "commit {}: {} of {} blobs arrived", frame,
                          blobs.size(), blob_count);
    for (const auto& [id, blob] : blobs)
        if (blob.size() != totals[id])
            return make_error(ErrorCode::parse_error, "commit {}: blob {} incomplete", frame, id);
    return blobs;
}

Result<Commit> decode_parsed(const commit_pb::Commit& w,
                             const std::vector<const commit_pb::BulkChunk*>& chunks) {
    auto blobs = assemble_blobs(chunks, w.frame(), w.blob_count());
    if (!blobs) return blobs.error();
    Commit c;
    c.frame = w.frame();
    c.base_commit = w.base_commit();
    c.is_snapshot = w.is_snapshot();
    c.ops.resize(std::size_t(w.ops_size()));
    for (int i = 0; i < w.ops_size(); ++i) {
        const char* name = "";
        if (Status s = codec::decode_op(w.ops(i), *blobs, c.ops[std::size_t(i)], name); !s)
            return make_error(ErrorCode::parse_error, "commit {}: op {} {}: {}", c.frame, i, name,
                              s.error().message);
    }
    return c;
}

}  // namespace

std::size_t EncodedCommit::total_bytes() const {
    std::size_t n = commit.size();
    for (const std::string& c : chunks)
        n += c.size();
    return n;
}

EncodedCommit encode_commit(const Commit& commit, std::size_t max_chunk_bytes) {
    commit_pb::Commit w;
    w.set_frame(commit.frame);
    w.set_base_commit(commit.base_commit);
    w.set_is_snapshot(commit.is_snapshot);
    codec::BlobWriter blobs(commit.frame, max_chunk_bytes);
    for (const CommitOp& op : commit.ops)
        codec::encode_op(op, *w.add_ops(), blobs);
    w.set_blob_count(blobs.count());
    return EncodedCommit{w.SerializeAsString(), blobs.take()};
}

Result<Commit> decode_commit(const std::string& commit_bytes,
                             const std::vector<std::string>& chunks) {
    commit_pb::Commit w;
    if (!w.ParseFromString(commit_bytes))
        return make_error(ErrorCode::parse_error, "malformed commit message");
    std::vector<commit_pb::BulkChunk> parsed(chunks.size());
    std::vector<const commit_pb::BulkChunk*> views;
    for (std::size_t k = 0; k < chunks.size(); ++k) {
        if (!parsed[k].ParseFromString(chunks[k]))
            return make_error(ErrorCode::parse_error, "commit {}: malformed bulk chunk", w.frame());
        views.push_back(&parsed[k]);
    }
    return decode_parsed(w, views);
}

Result<Commit> decode_commit(const ParsedCommit& commit,
                             const std::vector<std::shared_ptr<const ParsedChunk>>& chunks) {
    std::vector<const commit_pb::BulkChunk*> views;
    for (const auto& c : chunks)
        views.push_back(&c->message);
    return decode_parsed(commit.message, views);
}

}  // namespace pathfarm
