// The integer hash under every per-sample random number (docs/determinism.md), written once in
// the subset of C++ and OpenCL C that both compilers read: common/base/hash.h wraps it for C++,
// and the OpenCL kernels are compiled with this very text ahead of theirs
// (tracer-node/CMakeLists.txt), so the two backends cannot drift apart. Include guards, not
// #pragma once: OpenCL C sees the text pasted, not included.
#ifndef PATHFARM_COMMON_BASE_HASH_SHARED_H
#define PATHFARM_COMMON_BASE_HASH_SHARED_H

#ifdef __OPENCL_VERSION__
typedef uint pf_u32;
#define PF_SHARED
#else
#include <cstdint>
namespace pathfarm {
typedef uint32_t pf_u32;
#define PF_SHARED inline constexpr
#endif

// A 32-bit integer finaliser with good avalanche (Wellons' "lowbias32", public domain).
PF_SHARED pf_u32 pf_hash_u32(pf_u32 x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

// hash_words: the running hash starts at this value and folds in one word at a time.
#define PF_HASH_WORDS_START 0x9e3779b9U
PF_SHARED pf_u32 pf_hash_fold(pf_u32 h, pf_u32 word) {
    return pf_hash_u32(h ^ pf_hash_u32(word + 0x632be5abU));
}
PF_SHARED pf_u32 pf_hash_words4(pf_u32 a, pf_u32 b, pf_u32 c, pf_u32 d) {
    return pf_hash_fold(pf_hash_fold(pf_hash_fold(pf_hash_fold(PF_HASH_WORDS_START, a), b), c), d);
}

#ifndef __OPENCL_VERSION__
}  // namespace pathfarm
#endif
#endif  // PATHFARM_COMMON_BASE_HASH_SHARED_H
