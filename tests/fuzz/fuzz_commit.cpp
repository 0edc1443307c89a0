// The commit codec: a Commit message's bytes and its bulk chunks, as the coordinator's diff
// arrives at a tracer. Input layout (make_seeds writes it): a byte with the number of chunks
// (mod 4), each chunk as a 4-byte big-endian length and its bytes, then the commit.
#include <string>
#include <vector>

#include "common/commit/commit_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const char* p = reinterpret_cast<const char*>(data);
    std::size_t at = 1;
    std::vector<std::string> chunks;
    for (int i = 0; i < data[0] % 4; ++i) {
        if (size - at < 4) return 0;
        std::size_t n = 0;
        for (int b = 0; b < 4; ++b)
            n = (n << 8) | data[at + b];
        at += 4;
        if (n > size - at) return 0;
        chunks.emplace_back(p + at, n);
        at += n;
    }
    (void)pathfarm::decode_commit(std::string(p + at, size - at), chunks);
    return 0;
}
