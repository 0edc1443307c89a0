// Wire encoding of commits (the only place in common, with net/, that sees protobuf).
#pragma once

#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/commit/commit.h"

namespace pathfarm {

inline constexpr std::size_t kMaxChunkBytes = 256 * 1024;     // bulk payload chunk size
inline constexpr std::size_t kInlineVertexBytes = 16 * 1024;  // larger vertex ranges become blobs

// One serialised Commit message plus the serialised BulkChunk messages of its blobs.
struct EncodedCommit {
    std::string commit;
    std::vector<std::string> chunks;
    std::size_t total_bytes() const;
};

EncodedCommit encode_commit(const Commit& commit, std::size_t max_chunk_bytes = kMaxChunkBytes);
// Rebuilds the commit from its messages; malformed, missing or inconsistent data is an error.
Result<Commit> decode_commit(const std::string& commit_bytes,
                             const std::vector<std::string>& chunks);

}  // namespace pathfarm
