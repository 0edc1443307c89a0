// Sends a commit through the real wire codec (small chunks, to exercise reassembly).
#pragma once

#include <gtest/gtest.h>

#include "common/commit/commit_codec.h"

namespace pathfarm::test {

inline Commit through_wire(const Commit& c, std::size_t chunk_bytes = 4096) {
    const EncodedCommit e = encode_commit(c, chunk_bytes);
    auto d = decode_commit(e.commit, e.chunks);
    EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().message);
    return d.ok() ? *d : Commit{};
}

}  // namespace pathfarm::test
