// Integer hashing used for deterministic per-sample randomness and content hashes.
#pragma once

#include <cstdint>
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

}  // namespace pathfarm
