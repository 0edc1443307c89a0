// The scrambling of PixelSampler (common/sampling/rng.h) in the subset of C++ and OpenCL C
// both compilers read, like common/base/hash_shared.h: Owen-scrambled Sobol pairs whose
// sample index is shuffled per pair, each decided by hashes of the pixel and the pair. The
// OpenCL kernels get this text ahead of theirs, so both backends draw the same numbers for
// every sample, bit for bit (docs/determinism.md).
#ifndef PATHFARM_COMMON_SAMPLING_SAMPLER_SHARED_H
#define PATHFARM_COMMON_SAMPLING_SAMPLER_SHARED_H

#ifndef __OPENCL_VERSION__
#include "common/base/hash_shared.h"
namespace pathfarm {
#endif

PF_SHARED pf_u32 pf_reverse_bits(pf_u32 x) {
    x = ((x & 0x55555555U) << 1) | ((x >> 1) & 0x55555555U);
    x = ((x & 0x33333333U) << 2) | ((x >> 2) & 0x33333333U);
    x = ((x & 0x0f0f0f0fU) << 4) | ((x >> 4) & 0x0f0f0f0fU);
    x = ((x & 0x00ff00ffU) << 8) | ((x >> 8) & 0x00ff00ffU);
    return (x << 16) | (x >> 16);
}

// The Laine-Karras permutation (Burley 2020, "Practical Hash-based Owen Scrambling"): bit j of
// the result flips depending only on the seed and on bits below j.
PF_SHARED pf_u32 pf_laine_karras(pf_u32 x, pf_u32 seed) {
    x += seed;
    x ^= x * 0x6c50b47cU;
    x ^= x * 0xb82f1e52U;
    x ^= x * 0xc7afe638U;
    x ^= x * 0x8d22f6e6U;
    return x;
}

// Dimension pair `pair` of a pixel sample: its index shuffle seed, then the x and y scrambles.
PF_SHARED pf_u32 pf_pair_seed(pf_u32 pixel_hash, pf_u32 pair) {
    return pf_hash_u32(pixel_hash ^ (pair * 0x9e3779b9U));
}
PF_SHARED pf_u32 pf_x_scramble_seed(pf_u32 pair_seed) {
    return pf_hash_u32(pair_seed ^ 0x68bc21ebU);
}
PF_SHARED pf_u32 pf_y_scramble_seed(pf_u32 pair_seed) {
    return pf_hash_u32(pair_seed ^ 0x02e5be93U);
}

// 32 random bits to [0, 1) with 24 bits of precision (never 1).
PF_SHARED float pf_bits_to_unit_float(pf_u32 bits) {
    return (float)(bits >> 8) * 5.9604644775390625e-8f;
}

#ifndef __OPENCL_VERSION__
}  // namespace pathfarm
#endif
#endif  // PATHFARM_COMMON_SAMPLING_SAMPLER_SHARED_H
