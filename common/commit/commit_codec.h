// Wire encoding of commits: a Commit message plus the BulkChunk messages of its large payloads
// (DESIGN.md, "The frame" step 3; STYLE.md §8). The protobuf side stays in the codec's .cpp
// files (codec_internal.h); every op's encode and decode sit side by side in op_codec.cpp.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/commit/commit.h"

namespace pathfarm {

inline constexpr std::size_t kMaxChunkBytes = 256 * 1024;     // bulk payload chunk size
inline constexpr std::size_t kInlineVertexBytes = 16 * 1024;  // larger payloads become blobs

// One serialised Commit message plus the serialised BulkChunk messages of its blobs.
struct EncodedCommit {
    std::string commit;
    std::vector<std::string> chunks;
    std::size_t total_bytes() const;
};

EncodedCommit encode_commit(const Commit& commit, std::size_t max_chunk_bytes = kMaxChunkBytes);

// Rebuilds the commit from its messages. Malformed, missing or inconsistent data is an error
// that names the commit, the op and the field: "commit 12: op 3 SetMeshBvh: nodes: 31 bytes,
// not a multiple of 32".
Result<Commit> decode_commit(const std::string& commit_bytes,
                             const std::vector<std::string>& chunks);

// A Commit and BulkChunk message already parsed out of a received Envelope (common/wire), so a
// tracer parses every commit once.
struct ParsedCommit;
struct ParsedChunk;
Result<Commit> decode_commit(const ParsedCommit& commit,
                             const std::vector<std::shared_ptr<const ParsedChunk>>& chunks);

}  // namespace pathfarm
