// Integer hashing used for deterministic per-sample randomness and content hashes.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <initializer_list>

#include "common/base/hash_shared.h"

namespace pathfarm {

// A 32-bit integer finaliser with good avalanche (hash_shared.h, which OpenCL reads too).
constexpr uint32_t hash_u32(uint32_t x) { return pf_hash_u32(x); }

// Order-dependent combination of several 32-bit words into one well-mixed word.
constexpr uint32_t hash_words(std::initializer_list<uint32_t> words) {
    uint32_t h = PF_HASH_WORDS_START;
    for (uint32_t w : words)
        h = pf_hash_fold(h, w);
    return h;
}

// 64-bit FNV-1a over bytes, for content hashes of scene data.
constexpr uint64_t fnv1a64(const unsigned char* data, std::size_t size,
                           uint64_t h = 0xcbf29ce484222325ULL) {
    for (std::size_t i = 0; i < size; ++i)
        h = (h ^ data[i]) * 0x100000001b3ULL;
    return h;
}

// A content hash eight bytes a step (FNV-1a's byte steps cost a millisecond a frame on a
// scene of 12k triangles): for caches that compare contents within one process, never across
// builds or machines.
inline uint64_t hash_bytes_fast(const void* data, std::size_t size,
                                uint64_t h = 0xcbf29ce484222325ULL) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= size; i += 8) {
        uint64_t w;
        std::memcpy(&w, bytes + i, 8);
        h = std::rotl((h ^ w) * 0x9e3779b97f4a7c15ULL, 29);
    }
    return fnv1a64(bytes + i, size - i, h);
}

}  // namespace pathfarm
